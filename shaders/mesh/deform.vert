// A glTF part whose vertices move themselves, posed by transform feedback: morph targets
// first (MORPH_TARGETS: v + sum_i m_i dv_i, normals likewise), then the skin (SKINNED:
// sum_k w_k P_jk v with P_j = W_j(t) IBM_j; world/node_animation.py). The result is written
// over the mesh's vertex buffer before the frame's passes run, so every pass draws the
// posed mesh with its usual program. Only a scene with such a part compiles this.
in vec3 in_position;
in vec3 in_normal;
in vec2 in_uv;
#ifdef SKINNED
in vec4 in_joints;
in vec4 in_weights;
uniform mat4 u_joints[JOINT_COUNT];
#endif
#ifdef MORPH_TARGETS
// per target, per vertex: position delta xyz, normal delta xyz
layout(std430, binding = 5) readonly buffer MorphDeltas {
    float deltas[];
};
uniform float u_morph[MORPH_TARGETS];
uniform int u_vertex_count;
#endif

out vec3 out_position;
out vec3 out_normal;
out vec2 out_uv;

void main() {
    vec3 position = in_position;
    vec3 normal = in_normal;
#ifdef MORPH_TARGETS
    for (int t = 0; t < MORPH_TARGETS; ++t) {
        int base = (t * u_vertex_count + gl_VertexID) * 6;
        position += u_morph[t] * vec3(deltas[base], deltas[base + 1], deltas[base + 2]);
        normal += u_morph[t] * vec3(deltas[base + 3], deltas[base + 4], deltas[base + 5]);
    }
#endif
#ifdef SKINNED
    mat4 skin = in_weights.x * u_joints[int(in_joints.x)] + in_weights.y * u_joints[int(in_joints.y)]
              + in_weights.z * u_joints[int(in_joints.z)] + in_weights.w * u_joints[int(in_joints.w)];
    position = (skin * vec4(position, 1.0)).xyz;
    // normals by the inverse transpose; a joint that flattens the mesh leaves the normal as it was
    mat3 linear = mat3(skin);
    normal = abs(determinant(linear)) > 1e-20 ? transpose(inverse(linear)) * normal : normal;
#endif
    float len = length(normal);
    out_position = position;
    out_normal = len > 0.0 ? normal / len : in_normal;
    out_uv = in_uv;
}
