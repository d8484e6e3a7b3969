"""The shading equations of ``render.mode: shaded``, once, in NumPy.

This is the lighting model of docs/scene-notes.md ("Lighting model"), the same formulas the
GPU evaluates in shaders/lighting/*.glsl, written for arrays of surface points so the
reference renderer can shade every sample of a frame at once. Tests hold both
implementations to each other (tests/test_raytrace_shading.py).

Conventions: every function is vectorised over a leading axis of P points; vectors are
float64 arrays of shape (P, 3), scalars per point (P,). Light directions are the way light
travels; ``l`` below is the unit vector from the point towards the light.
"""
from __future__ import annotations

import numpy as np

from scenerender.raytrace import ambient_fit, sheen_fit


def safe_normalize(v: np.ndarray, fallback: np.ndarray | None = None) -> np.ndarray:
    """(P, 3) float64 -> unit vectors; rows with squared length <= 1e-20 become ``fallback``
    ((P, 3) or (3,), default +Y), so no NaN ever leaves here, as in shaders/common/math.glsl."""
    length2 = np.sum(v * v, axis=-1, keepdims=True)
    if fallback is None:
        fallback = np.array([0.0, 1.0, 0.0])
    fallback = np.broadcast_to(fallback, v.shape)
    ok = length2 > 1e-20
    return np.where(ok, v / np.sqrt(np.where(ok, length2, 1.0)), fallback)


def attenuation(coefficients, distance: np.ndarray) -> np.ndarray:
    """1 / (c + l d + q d^2) for (3,) coefficients (c, l, q) and (P,) distances -> (P,)."""
    c, linear, quadratic = (float(x) for x in coefficients)
    return 1.0 / np.maximum(c + linear * distance + quadratic * distance * distance, 1e-6)


def range_window(light_range: float | None, distance: np.ndarray) -> np.ndarray:
    """(P,) KHR_lights_punctual's recommended window clamp(1 - (d / range)^4, 0, 1) for (P,)
    distances (it multiplies the falloff); 1 where the light has no range (None)."""
    if light_range is None:
        return np.ones_like(distance)
    return np.clip(1.0 - (distance / light_range) ** 4, 0.0, 1.0)


def spot_cone(cos_inner: float, cos_outer: float, cos_angle: np.ndarray, falloff: str = "smooth") -> np.ndarray:
    """(P,) cone factor: 1 inside the inner cone, 0 outside the outer, between them of the
    linear ramp t from cos_outer to cos_inner its smoothstep (``falloff`` "smooth") or its
    square ("gltf", KHR_lights_punctual's implementation note); ``cos_inner == cos_outer``
    is a hard edge (a point exactly on it is lit)."""
    width = cos_inner - cos_outer
    if width <= 0.0:
        return (cos_angle >= cos_outer).astype(np.float64)
    x = np.clip((cos_angle - cos_outer) / width, 0.0, 1.0)
    if falloff == "gltf":
        return x * x
    return x * x * (3.0 - 2.0 * x)


def specular_lobe(n: np.ndarray, l: np.ndarray, v: np.ndarray, shininess: np.ndarray,
                  model: str) -> np.ndarray:
    """(P,) lobe: (R.V)^Ns for ``model`` "phong", (N.H)^Ns for "blinn_phong"; 0 where the
    cosine is not positive, so Ns = 0 gives a flat lobe, never NaN.

    n, l, v: (P, 3) unit vectors; shininess: (P,) or scalar."""
    if model == "phong":
        reflected = 2.0 * np.sum(n * l, axis=-1, keepdims=True) * n - l
        c = np.sum(reflected * v, axis=-1)
    else:
        c = np.sum(n * safe_normalize(l + v, n), axis=-1)
    positive = c > 0.0
    return np.where(positive, np.power(np.where(positive, c, 1.0), shininess), 0.0)


def direct_term(n: np.ndarray, l: np.ndarray, v: np.ndarray, radiance: np.ndarray, base: np.ndarray,
                specular: np.ndarray, shininess: np.ndarray, model: str) -> np.ndarray:
    """One light's contribution, (P, 3): radiance * (base * max(N.L, 0) + Ks * lobe), and
    zero where N.L <= 0 (the lobe too: an unlit side has no highlight).

    radiance: (P, 3) light colour x intensity x attenuation x cone x visibility;
    base, specular: (P, 3) linear Kd (times its map) and Ks; shininess (P,)."""
    n_dot_l = np.sum(n * l, axis=-1)
    lit = n_dot_l > 0.0
    lobe = specular_lobe(n, l, v, shininess, model)
    term = radiance * (base * n_dot_l[:, None] + specular * lobe[:, None])
    return np.where(lit[:, None], term, 0.0)


# -- the pbr model (shaders/lighting/pbr.glsl) ---------------------------------------------------

PBR_MIN_ALPHA = 0.002  # alpha = roughness^2 is kept above this, as on the GPU


def _dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.sum(a * b, axis=-1)


def ggx_distribution(n_dot_h: np.ndarray, alpha: np.ndarray) -> np.ndarray:
    """(P,) GGX / Trowbridge-Reitz D = alpha^2 / (pi ((N.H)^2 (alpha^2 - 1) + 1)^2)."""
    a2 = alpha * alpha
    d = n_dot_h * n_dot_h * (a2 - 1.0) + 1.0
    return a2 / (np.pi * d * d)


def smith_visibility(n_dot_v: np.ndarray, n_dot_l: np.ndarray, alpha: np.ndarray) -> np.ndarray:
    """(P,) height-correlated Smith V = G / (4 N.L N.V):
    0.5 / (N.L sqrt((N.V)^2 (1 - a^2) + a^2) + N.V sqrt((N.L)^2 (1 - a^2) + a^2))."""
    a2 = alpha * alpha
    from_view = n_dot_l * np.sqrt(n_dot_v * n_dot_v * (1.0 - a2) + a2)
    from_light = n_dot_v * np.sqrt(n_dot_l * n_dot_l * (1.0 - a2) + a2)
    total = from_view + from_light
    return np.where(total > 0.0, 0.5 / np.where(total > 0.0, total, 1.0), 0.0)


def fresnel_schlick(f0: np.ndarray, v_dot_h: np.ndarray) -> np.ndarray:
    """(P, 3) F = F0 + (1 - F0) (1 - V.H)^5."""
    return f0 + (1.0 - f0) * ((1.0 - v_dot_h) ** 5)[:, None]


def pbr_alpha(roughness: np.ndarray) -> np.ndarray:
    return np.maximum(np.asarray(roughness, dtype=np.float64) ** 2, PBR_MIN_ALPHA)


def pbr_brdf(n: np.ndarray, l: np.ndarray, v: np.ndarray, base: np.ndarray, metallic: np.ndarray,
             roughness: np.ndarray) -> np.ndarray:
    """(P, 3) glTF 2.0's metallic-roughness BRDF f(l, v) (Appendix B):
    f = (1 - F) (1 - metallic) base / pi + F D V, F0 = mix(0.04, base, metallic); zero
    where N.L <= 0 or N.V <= 0 (it is symmetric in l and v: f(l, v) = f(v, l)).

    n, l, v: (P, 3) unit vectors; base (P, 3); metallic, roughness (P,)."""
    n_dot_l, n_dot_v = _dot(n, l), _dot(n, v)
    h = safe_normalize(l + v, n)
    alpha = pbr_alpha(roughness)
    metallic = np.asarray(metallic, dtype=np.float64)[:, None]
    f0 = 0.04 * (1.0 - metallic) + base * metallic
    fresnel = fresnel_schlick(f0, np.clip(_dot(v, h), 0.0, 1.0))
    specular = ggx_distribution(np.clip(_dot(n, h), 0.0, 1.0), alpha) * smith_visibility(
        np.clip(n_dot_v, 0.0, 1.0), np.clip(n_dot_l, 0.0, 1.0), alpha)
    f = (1.0 - fresnel) * (1.0 - metallic) * base / np.pi + fresnel * specular[:, None]
    return np.where(((n_dot_l > 0.0) & (n_dot_v > 0.0))[:, None], f, 0.0)


def pbr_direct_term(n: np.ndarray, l: np.ndarray, v: np.ndarray, radiance: np.ndarray, base: np.ndarray,
                    metallic: np.ndarray, roughness: np.ndarray, layers: dict | None = None) -> np.ndarray:
    """One light's contribution under the pbr model, (P, 3): radiance * pi f(l, v) N.L, the
    light units of the other models (Lambert's f = base / pi gives radiance base N.L); zero
    where N.L <= 0. As on the GPU, N.V is clamped to 0 rather than cut (a normal that
    turns from the eye still reflects). ``layers``: the points' layer values
    (``pbr_layers``), or None for a material without any."""
    n_dot_l = _dot(n, l)
    n_dot_v = np.clip(_dot(n, v), 0.0, 1.0)
    h = safe_normalize(l + v, n)
    alpha = pbr_alpha(roughness)
    metallic = np.asarray(metallic, dtype=np.float64)[:, None]
    v_dot_h = np.clip(_dot(v, h), 0.0, 1.0)
    n_dot_h = np.clip(_dot(n, h), 0.0, 1.0)
    if layers is None:
        f0 = 0.04 * (1.0 - metallic) + base * metallic
        fresnel = fresnel_schlick(f0, v_dot_h)
    else:
        f0 = layers["f0"] * (1.0 - metallic) + base * metallic
        f90 = layers["f90"][:, None] * (1.0 - metallic) + metallic
        fresnel = f0 + (f90 - f0) * ((1.0 - v_dot_h) ** 5)[:, None]
    specular = np.pi * ggx_distribution(n_dot_h, alpha) * smith_visibility(n_dot_v, np.clip(n_dot_l, 0.0, 1.0), alpha)
    if layers is not None and layers.get("anisotropy") is not None:
        turned = layers["anisotropy"] > 0.0
        if turned.any():
            specular = np.where(turned, np.pi * anisotropic_ggx(n, l, v, h, layers["anisotropy_t"], alpha,
                                                                layers["anisotropy"]), specular)
    diffuse_fresnel = fresnel
    if layers is not None and layers.get("iridescence") is not None and np.any(layers["iridescence"] > 0.0):
        # KHR_materials_iridescence: the thin film's Fresnel (at N.V, per point) mixed into
        # the specular Fresnel, its largest channel into what the diffuse part loses
        film = thin_film_fresnel(n_dot_v, layers["iridescence_ior"], layers["iridescence_thickness"], f0)
        weight = layers["iridescence"][:, None]
        diffuse_fresnel = fresnel + weight * (film.max(axis=1, keepdims=True) - fresnel)
        fresnel = fresnel + weight * (film - fresnel)
    diffuse_weight = (1.0 - metallic) if layers is None else (1.0 - metallic) * _kept(layers)
    term = ((1.0 - diffuse_fresnel) * diffuse_weight * base + fresnel * specular[:, None]) * n_dot_l[:, None]
    if layers is not None:
        term = _sheen_over(term, layers, n_dot_v, np.clip(n_dot_l, 0.0, 1.0), n_dot_h)
        # KHR_materials_clearcoat takes the coat's Fresnel at N.V, not V.H (its Layering
        # section), about the coat's own normal where it has one
        coat_n_dot_v, coat_n_dot_h, coat_n_dot_l = n_dot_v, n_dot_h, n_dot_l
        if layers.get("clearcoat_normal") is not None:
            coat_n = layers["clearcoat_normal"]
            coat_n_dot_v = np.clip(_dot(coat_n, v), 0.0, 1.0)
            coat_n_dot_h = np.clip(_dot(coat_n, h), 0.0, 1.0)
            coat_n_dot_l = np.maximum(_dot(coat_n, l), 0.0)
        coat = layers["clearcoat"] * coat_fresnel(coat_n_dot_v)
        coat_alpha = pbr_alpha(layers["clearcoat_roughness"])
        coat_lobe = np.pi * ggx_distribution(coat_n_dot_h, coat_alpha) * smith_visibility(
            coat_n_dot_v, np.clip(coat_n_dot_l, 0.0, 1.0), coat_alpha)
        term = term * (1.0 - coat)[:, None] + (coat * coat_lobe * coat_n_dot_l)[:, None]
    return np.where((n_dot_l > 0.0)[:, None], radiance * term, 0.0)


# CIE XYZ to linear Rec. 709 RGB (KHR_materials_iridescence's matrix)
_XYZ_TO_REC709 = np.array([[3.2404542, -1.5371385, -0.4985314],
                           [-0.9692660, 1.8760108, 0.0415560],
                           [0.0556434, -0.2040259, 1.0572252]])


def _film_sensitivity(opd: np.ndarray, shift: np.ndarray) -> np.ndarray:
    """(P, 3) linear RGB of the spectral integral of a phase shift (Belcour and Barla's
    Gaussian fit of the XYZ sensitivities, as the extension writes it): opd (P,) nanometres,
    shift (P, 3) radians."""
    phase = 2.0 * np.pi * opd[:, None] * 1.0e-9
    val = np.array([5.4856e-13, 4.4201e-13, 5.2481e-13])
    pos = np.array([1.6810e+06, 1.7953e+06, 2.2084e+06])
    var = np.array([4.3278e+09, 9.3046e+09, 6.6121e+09])
    xyz = val * np.sqrt(2.0 * np.pi * var) * np.cos(pos * phase + shift) * np.exp(-phase ** 2 * var)
    xyz[:, 0] += 9.7470e-14 * np.sqrt(2.0 * np.pi * 4.5282e+09) * np.cos(2.2399e+06 * phase[:, 0] + shift[:, 0]) \
        * np.exp(-4.5282e+09 * phase[:, 0] ** 2)
    return (xyz / 1.0685e-7) @ _XYZ_TO_REC709.T


def thin_film_fresnel(cos_theta: np.ndarray, film_ior: np.ndarray, thickness: np.ndarray,
                      base_f0: np.ndarray) -> np.ndarray:
    """(P, 3) KHR_materials_iridescence's Fresnel of a thin film of index ``film_ior`` and
    ``thickness`` nanometres (P,) over a base of F0 ``base_f0`` (P, 3), in air, seen at
    cosine ``cos_theta`` (P,): Schlick at both interfaces, the first two orders of the
    interference integrated over the spectrum (the extension's formulas; the optical path
    difference at the refracted angle, 2 n d cos theta_2). Total internal reflection gives 1."""
    cos1 = np.clip(cos_theta, 0.0, 1.0)
    sin2_sq = (1.0 / film_ior) ** 2 * (1.0 - cos1 ** 2)
    cos2_sq = 1.0 - sin2_sq
    cos2 = np.sqrt(np.maximum(cos2_sq, 0.0))
    r0 = ((film_ior - 1.0) / (film_ior + 1.0)) ** 2
    r12 = r0 + (1.0 - r0) * (1.0 - cos1) ** 5
    t121 = 1.0 - r12
    phi12 = np.where(film_ior < 1.0, np.pi, 0.0)
    phi21 = np.pi - phi12
    root = np.sqrt(np.clip(base_f0, 0.0, 0.9999))
    base_ior = (1.0 + root) / (1.0 - root)
    r1 = ((base_ior - film_ior[:, None]) / (base_ior + film_ior[:, None])) ** 2
    r23 = r1 + (1.0 - r1) * ((1.0 - cos2) ** 5)[:, None]
    phi23 = np.where(base_ior < film_ior[:, None], np.pi, 0.0)
    opd = 2.0 * film_ior * thickness * cos2
    phi = phi21[:, None] + phi23
    r123 = np.clip(r12[:, None] * r23, 1e-5, 0.9999)
    amplitude = np.sqrt(r123)
    rs = (t121 ** 2)[:, None] * r23 / (1.0 - r123)
    result = r12[:, None] + rs
    cm = rs - t121[:, None]
    for order in (1, 2):
        cm = cm * amplitude
        result = result + cm * 2.0 * _film_sensitivity(order * opd, order * phi)
    return np.where((cos2_sq < 0.0)[:, None], 1.0, np.maximum(result, 0.0))


def anisotropic_ggx(n: np.ndarray, l: np.ndarray, v: np.ndarray, h: np.ndarray, t: np.ndarray, alpha: np.ndarray,
                    strength: np.ndarray) -> np.ndarray:
    """(P,) D V of KHR_materials_anisotropy's GGX: alpha_t = mix(alpha, 1, strength^2) along
    the unit direction ``t`` (P, 3) (orthogonal to n), alpha_b = alpha along b = n x t:
    D = 1 / (pi alpha_t alpha_b ((T.H / alpha_t)^2 + (B.H / alpha_b)^2 + (N.H)^2)^2),
    V = 0.5 / (N.L |(alpha_t T.V, alpha_b B.V, N.V)| + N.V |(alpha_t T.L, alpha_b B.L, N.L)|),
    N.V and N.L clamped to [0, 1] as in ``pbr_direct_term``."""
    b = np.cross(n, t)
    alpha_t = alpha + (1.0 - alpha) * strength * strength
    alpha_b = alpha
    n_dot_h = np.clip(_dot(n, h), 0.0, 1.0)
    k = (_dot(t, h) / alpha_t) ** 2 + (_dot(b, h) / alpha_b) ** 2 + n_dot_h ** 2
    distribution = 1.0 / (np.pi * alpha_t * alpha_b * k * k)
    n_dot_v, n_dot_l = np.clip(_dot(n, v), 0.0, 1.0), np.clip(_dot(n, l), 0.0, 1.0)
    from_view = n_dot_l * np.sqrt((alpha_t * _dot(t, v)) ** 2 + (alpha_b * _dot(b, v)) ** 2 + n_dot_v ** 2)
    from_light = n_dot_v * np.sqrt((alpha_t * _dot(t, l)) ** 2 + (alpha_b * _dot(b, l)) ** 2 + n_dot_l ** 2)
    total = from_view + from_light
    return distribution * np.where(total > 0.0, 0.5 / np.where(total > 0.0, total, 1.0), 0.0)


def anisotropic_ambient_roughness(roughness: np.ndarray, strength: np.ndarray) -> np.ndarray:
    """(P,) the roughness whose isotropic lobe reflects about what KHR_materials_anisotropy's
    lobe does of a uniform light: alpha = sqrt((alpha_t^2 + alpha_b^2) / 2) (its directional
    albedo within 0.016 of the anisotropic one's for alpha 0.01 to 0.25, strength 0.3 to
    0.9); ``roughness`` where the strength is 0."""
    alpha = pbr_alpha(roughness)
    alpha_t = alpha + (1.0 - alpha) * strength * strength
    return np.where(strength > 0.0, np.sqrt(np.sqrt(0.5 * (alpha_t * alpha_t + alpha * alpha))), roughness)


def _sheen_over(term: np.ndarray, layers: dict, n_dot_v: np.ndarray, n_dot_l: np.ndarray,
                n_dot_h: np.ndarray) -> np.ndarray:
    """(P, 3) ``term`` (pi f_base N.L) under KHR_materials_sheen: times its albedo scaling
    min(1 - max(sheen) E(N.V), 1 - max(sheen) E(N.L)) (kept at 0 or above), plus the sheen's
    pi sheen_colour D V N.L (Charlie)."""
    color, roughness = layers["sheen_color"], layers["sheen_roughness"]
    strongest = color.max(axis=1)
    scaling = np.maximum(np.minimum(1.0 - strongest * sheen_fit.evaluate(n_dot_v, roughness),
                                    1.0 - strongest * sheen_fit.evaluate(n_dot_l, roughness)), 0.0)
    alpha = sheen_fit.sheen_alpha(roughness)
    lobe = np.pi * sheen_fit.charlie_distribution(n_dot_h, alpha) * sheen_fit.sheen_visibility(n_dot_v, n_dot_l, alpha)
    return term * scaling[:, None] + color * (lobe * n_dot_l)[:, None]


def pbr_through_term(n: np.ndarray, l: np.ndarray, v: np.ndarray, radiance: np.ndarray, base: np.ndarray,
                     metallic: np.ndarray, roughness: np.ndarray, transmission: np.ndarray, ior: np.ndarray,
                     f0: np.ndarray, f90: np.ndarray) -> np.ndarray:
    """(P, 3) what a light in direction ``l`` behind a transmissive surface (N.L < 0) gives
    through it towards ``v``, radiance * pi f_t |N.L| (zero where N.L >= 0):
    KHR_materials_transmission's BTDF, the specular lobe with l mirrored through the
    surface's plane, l_m = l - 2 (N.L) N, tinted: (1 - metallic) transmission base
    (1 - F(V.H_t)) pi D V N.L_m, h_t the half vector of l_m and v, at alpha_t = alpha
    clamp(2 ior - 2, 0, 1) (shaders/lighting/pbr.glsl, pbr_through). The base layer's alone.

    n, l, v: (P, 3) unit; radiance, base, f0 (the dielectric's F0): (P, 3); metallic,
    roughness, transmission, ior, f90: (P,)."""
    n_dot_l = -_dot(n, l)
    mirrored = l + 2.0 * n_dot_l[:, None] * n
    h = safe_normalize(mirrored + v, n)
    alpha = np.maximum(pbr_alpha(roughness) * np.clip(2.0 * ior - 2.0, 0.0, 1.0), PBR_MIN_ALPHA)
    n_dot_v = np.clip(_dot(n, v), 0.0, 1.0)
    lit = np.clip(n_dot_l, 0.0, 1.0)
    lobe = np.pi * ggx_distribution(np.clip(_dot(n, h), 0.0, 1.0), alpha) * smith_visibility(n_dot_v, lit, alpha)
    fresnel = f0 + (f90[:, None] - f0) * ((1.0 - np.clip(_dot(v, h), 0.0, 1.0)) ** 5)[:, None]
    tint = base * ((1.0 - metallic) * transmission)[:, None]
    term = radiance * tint * (1.0 - fresnel) * (lobe * lit)[:, None]
    return np.where((n_dot_l > 0.0)[:, None], term, 0.0)


def _kept(layers: dict) -> np.ndarray:
    """(P, 1) the share of the diffuse part that stays diffuse: 1 - transmission
    (KHR_materials_transmission; what passes through is raytrace/transmission.py's)."""
    return 1.0 - layers["transmission"][:, None]


def coat_fresnel(cosine: np.ndarray) -> np.ndarray:
    """(P,) the clear coat's Fresnel, F0 0.04 (ior 1.5): 0.04 + 0.96 (1 - cos)^5."""
    return 0.04 + 0.96 * (1.0 - cosine) ** 5


LAYER_KEYS = ("f0", "f90", "clearcoat", "clearcoat_roughness", "sheen_color", "sheen_roughness", "transmission",
              "iridescence", "iridescence_ior", "iridescence_thickness")


def pbr_layers(points: dict) -> dict | None:
    """The layer values of ``points`` (arrays per point: "layered" (P,) bool, f0 (P, 3),
    f90, clearcoat, clearcoat_roughness (P,), sheen_color (P, 3), sheen_roughness, transmission (P,)), or None where no point has a layer (then the
    model's own formulas apply, to the bit)."""
    if not np.any(points["layered"]):
        return None
    layers = {key: points[key] for key in LAYER_KEYS}
    if "anisotropy_t" in points:  # KHR_materials_anisotropy: its strength (P,), its direction (P, 3)
        layers.update(anisotropy=points["anisotropy"], anisotropy_t=points["anisotropy_t"])
    if "clearcoat_normal" in points:  # the coat's own normal (P, 3), from clearcoatNormalTexture
        layers["clearcoat_normal"] = points["clearcoat_normal"]
    return layers


def pbr_ambient(n: np.ndarray, v: np.ndarray, base: np.ndarray, metallic: np.ndarray,
                roughness: np.ndarray, layers: dict | None = None) -> np.ndarray:
    """(P, 3) what a uniform ambient light of radiance 1 gives under the pbr model, as the
    GPU has it: the BRDF's hemisphere integrals from the committed fit
    (scenerender.raytrace.ambient_fit): specular F0 A + B, diffuse
    (1 - metallic) base (1 - F0) (1 - Cd). With ``layers`` (``pbr_layers``): specular
    F0 A + F90 B, diffuse (1 - metallic) base ((1 - F0) - (F90 - F0) Cd), both times
    1 - max(sheen) E(N.V) (kept at 0 or above) with the sheen's sheen_colour E(N.V) added
    (sheen_fit), then times 1 - c Fc(N.V), plus the coat's c (0.04 A_c + B_c)."""
    n_dot_v = np.clip(_dot(n, v), 0.0, 1.0)
    if layers is not None and layers.get("anisotropy") is not None:
        roughness = anisotropic_ambient_roughness(roughness, layers["anisotropy"])
    scale, bias, diffuse_fresnel = ambient_fit.evaluate(n_dot_v, roughness)
    metallic = np.asarray(metallic, dtype=np.float64)[:, None]
    if layers is None:
        f0 = 0.04 * (1.0 - metallic) + base * metallic
        diffuse = base * (1.0 - metallic) * (1.0 - f0) * (1.0 - diffuse_fresnel)[:, None]
        return diffuse + f0 * scale[:, None] + bias[:, None]
    f0 = layers["f0"] * (1.0 - metallic) + base * metallic
    f90 = layers["f90"][:, None] * (1.0 - metallic) + metallic
    diffuse = base * (1.0 - metallic) * _kept(layers) * ((1.0 - f0) - (f90 - f0) * diffuse_fresnel[:, None])
    specular = f0 * scale[:, None] + f90 * bias[:, None]
    if layers.get("iridescence") is not None and np.any(layers["iridescence"] > 0.0):
        # the thin film's Fresnel at N.V in the specular weight's F0 (F90 1), its largest
        # channel in what the diffuse part keeps, mixed in by the iridescence
        film = thin_film_fresnel(n_dot_v, layers["iridescence_ior"], layers["iridescence_thickness"], f0)
        weight = layers["iridescence"][:, None]
        specular = specular + weight * (film * scale[:, None] + bias[:, None] - specular)
        diffuse = diffuse + weight * (base * (1.0 - metallic) * _kept(layers) * (1.0 - film.max(axis=1, keepdims=True)) - diffuse)
    sheen = sheen_fit.evaluate(n_dot_v, layers["sheen_roughness"])
    sheen_through = np.maximum(1.0 - layers["sheen_color"].max(axis=1) * sheen, 0.0)
    sheened = (diffuse + specular) * sheen_through[:, None] + layers["sheen_color"] * sheen[:, None]
    coat_n_dot_v = n_dot_v
    if layers.get("clearcoat_normal") is not None:  # the coat's own normal
        coat_n_dot_v = np.clip(_dot(layers["clearcoat_normal"], v), 0.0, 1.0)
    coat_scale, coat_bias, _ = ambient_fit.evaluate(coat_n_dot_v, layers["clearcoat_roughness"])
    through = 1.0 - layers["clearcoat"] * coat_fresnel(coat_n_dot_v)
    coat = layers["clearcoat"] * (0.04 * coat_scale + coat_bias)
    return sheened * through[:, None] + coat[:, None]


def ambient_term(ambient: np.ndarray, ka: np.ndarray, base: np.ndarray) -> np.ndarray:
    """(P, 3) La * Ka * base: ambient (3,) summed ambient light, ka and base (P, 3)."""
    return ambient[None, :] * ka * base


def fog_visibility(distance: np.ndarray, mode: str, density: float, start: float, end: float) -> np.ndarray:
    """(P,) fraction of the surface colour that survives fog at eye distance ``distance``:
    exp(-d rho), exp(-(d rho)^2) or (end - d) / (end - start) clamped to [0, 1]."""
    if mode == "exp":
        return np.exp(-distance * density)
    if mode == "exp2":
        return np.exp(-(distance * density) ** 2)
    return np.clip((end - distance) / (end - start), 0.0, 1.0)


def apply_fog(color: np.ndarray, distance: np.ndarray, fog_color: np.ndarray, mode: str, density: float,
              start: float, end: float) -> np.ndarray:
    """(P, 3) colour mixed towards ``fog_color`` (3,) in linear light."""
    keep = fog_visibility(distance, mode, density, start, end)[:, None]
    return fog_color[None, :] * (1.0 - keep) + color * keep


