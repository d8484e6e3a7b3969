// Object ids: the index of the drawn object in the world's list, plus one (0 is the
// background), into an unsigned integer target. With BEHIND_LAYER (the opaque surfaces,
// drawn first) the same id goes to a second target too, which the transparent surfaces
// drawn after leave alone: it keeps the nearest opaque object behind them.
uniform uint u_object_id;
layout(location = 0) out uint frag_id;
#ifdef BEHIND_LAYER
layout(location = 1) out uint frag_behind_id;
#endif

void main() {
    frag_id = u_object_id;
#ifdef BEHIND_LAYER
    frag_behind_id = u_object_id;
#endif
}
