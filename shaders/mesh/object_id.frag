// Object ids: the index of the drawn object in the world's list, plus one (0 is the
// background), into an unsigned integer target.
uniform uint u_object_id;
out uint frag_id;

void main() {
    frag_id = u_object_id;
}
