// Depth prepass: depth only, so the shading pass runs once per visible pixel.
void main() {
}
