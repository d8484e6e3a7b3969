// The specular lobe: Phong (reflection . view) or Blinn-Phong (normal . half vector),
// chosen when the program is assembled. Shininess 0 gives a constant lobe, never NaN:
// pow(x, y) is undefined for x <= 0, so those cases return 0 before pow runs.

float specular_lobe(vec3 n, vec3 l, vec3 v, float shininess) {
#ifdef SPECULAR_PHONG
    float c = dot(reflect(-l, n), v);
#else
    float c = dot(n, safe_normalize(l + v, n));
#endif
    return c > 0.0 ? pow(c, shininess) : 0.0;
}
