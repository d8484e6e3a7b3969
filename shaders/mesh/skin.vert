// Skinning by transform feedback: a skinned glTF part's vertices placed by its joints,
// sum_k w_k P_jk v with P_j = W_j(t) IBM_j (world/node_animation.py), written over the
// mesh's vertex buffer before the frame's passes run, so every pass draws the skinned
// mesh with today's programs. Only a scene with a skinned part compiles this.
in vec3 in_position;
in vec3 in_normal;
in vec2 in_uv;
in vec4 in_joints;
in vec4 in_weights;

uniform mat4 u_joints[JOINT_COUNT];

out vec3 out_position;
out vec3 out_normal;
out vec2 out_uv;

void main() {
    mat4 skin = in_weights.x * u_joints[int(in_joints.x)] + in_weights.y * u_joints[int(in_joints.y)]
              + in_weights.z * u_joints[int(in_joints.z)] + in_weights.w * u_joints[int(in_joints.w)];
    out_position = (skin * vec4(in_position, 1.0)).xyz;
    // normals by the inverse transpose; a joint that flattens the mesh leaves the normal as it was
    mat3 linear = mat3(skin);
    float volume = determinant(linear);
    vec3 normal = abs(volume) > 1e-20 ? transpose(inverse(linear)) * in_normal : in_normal;
    float len = length(normal);
    out_normal = len > 0.0 ? normal / len : in_normal;
    out_uv = in_uv;
}
