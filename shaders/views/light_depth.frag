// mode: light_depth. The first shadowed light's depth map (linear, black near, white far);
// a point light's six cube faces are laid out 3 x 2 (+X -X +Y / -Y +Z -Z).
in vec2 v_uv;
uniform sampler2D u_atlas;  // sampled without depth comparison
uniform vec4 u_tiles[6];    // uv origin and size of each view's tile
uniform int u_tile_count;
out vec4 frag_color;

void main() {
    vec2 uv = v_uv;
    int index = 0;
    if (u_tile_count == 6) {
        vec2 cell = floor(uv * vec2(3.0, 2.0));
        index = int(cell.x) + 3 * (1 - int(cell.y));
        uv = fract(uv * vec2(3.0, 2.0));
    }
    vec4 tile = u_tiles[index];
    float depth = texture(u_atlas, tile.xy + uv * tile.zw).r;
    frag_color = vec4(vec3(depth), 1.0);
}
