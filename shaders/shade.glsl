// vergence — surface shading shared by the G-buffer and the eyes.
// Needs lighting.glsl, `shadow_map` (sampler2DShadow) and `textures[]`.

// 3x3 percentage-closer filter over the hardware 2x2 compare.
float sun_visibility(vec3 world, vec3 n)
{
    float ndl = dot(n, u.sun_dir.xyz);
    // Normal offset against acne, scaled by the shadow texel's world size.
    vec3 p = world + n * u.sun_dir.w * 1.5 * (1.0 - ndl);
    vec4 c = u.light_view_proj * vec4(p, 1.0);
    vec3 s = vec3(c.xy * 0.5 + 0.5, c.z);
    if (any(lessThan(s.xy, vec2(0.0))) || any(greaterThan(s.xy, vec2(1.0))) || s.z > 1.0)
        return 1.0;
    vec2 texel = 1.0 / vec2(textureSize(shadow_map, 0));
    float v = 0.0;
    for (int y = -1; y <= 1; y++)
        for (int x = -1; x <= 1; x++)
            v += texture(shadow_map, vec3(s.xy + vec2(x, y) * texel, s.z - 0.0015));
    return v / 9.0;
}

// Lit, fogged, tone-mapped and sRGB-encoded colour of a surface point. The
// view vector is the centre camera's, so both eyes of the warp and of the
// two-camera baseline shade alike.
vec3 shade_surface(vec3 world, vec3 normal, bool front, vec4 base)
{
    vec3 n = normalize(normal);
    if (!front)
        n = -n;
    vec3 to_eye = u.camera_pos.xyz - world;
    float dist = length(to_eye);
    vec3 v = to_eye / dist;
    float ndl = max(dot(n, u.sun_dir.xyz), 0.0);
    float vis = ndl > 0.0 ? sun_visibility(world, n) : 0.0;
    vec3 hemi = mix(u.ground_color.rgb, u.sky_zenith.rgb * 0.8 + u.sky_horizon.rgb * 0.2, n.y * 0.5 + 0.5);
    vec3 h = normalize(u.sun_dir.xyz + v);
    float spec = pow(max(dot(n, h), 0.0), 48.0) * 0.12 * u.warp2.y;
    vec3 lit = base.rgb * (u.sun_color.rgb * ndl * vis + hemi * u.sun_color.w) + u.sun_color.rgb * spec * vis;
    return linear_to_srgb(tonemap(apply_fog(lit, -v, dist)));
}

vec4 surface_base_color(vec4 vertex_color, vec2 uv)
{
    vec4 base = d.base_color * vertex_color;
    if (d.texture_index >= 0)
        base *= texture(textures[d.texture_index], uv);
    return base;
}
