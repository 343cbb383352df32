// vergence — surface shading shared by the G-buffer and the eyes.
// Needs lighting.glsl, `shadow_map` (sampler2DShadow) and `textures[]`.

// 3x3 percentage-closer filter over the 2x2 bilinear compare, as four
// gathers: the nine bilinear taps one texel apart cover a 4x4 block of
// texels with the separable weights (1 - f, 1, 1, f) of the taps' common
// fraction f, so the block's 16 compares give the same sum (up to the
// sampler's rounding of f) for 16 texel reads instead of 36 and no filter.
//
// Two cascades (render/shadow_gpu.c, shadow_gpu_setup): points nearer the centre camera than
// u.shadow.x (view depth) read the near one, the rest the whole scene's.
// The choice is arithmetic: lavapipe compiles a shader again for every new
// value of a uniform that alone decides a branch (common.glsl).
float sun_visibility(vec3 world, vec3 n)
{
    float ndl = dot(n, u.sun_dir.xyz);
    uint cascade = -(u.view * vec4(world, 1.0)).z < u.shadow.x ? 1u : 0u;
    // Normal offset against acne, scaled by the cascade's texel (world size).
    vec3 p = world + n * u.shadow[1u + cascade] * 1.5 * (1.0 - ndl);
    vec4 c = u.light_view_proj[cascade] * vec4(p, 1.0);
    vec3 s = vec3(c.xy * 0.5 + 0.5, c.z);
    if (any(lessThan(s.xy, vec2(0.0))) || any(greaterThan(s.xy, vec2(1.0))) || s.z > 1.0)
        return 1.0;
    // The cascade's square in the atlas: texel coordinates of the whole map.
    vec2 size = vec2(textureSize(shadow_map, 0)), t = s.xy * size.y - 0.5 + vec2(float(cascade) * size.y, 0.0);
    vec2 i = floor(t), f = t - i;
    // Each gather at a texel corner reads the 2x2 texels around it (texel
    // centres sit at k + 0.5): w, z on the row below the corner, x, y above.
    float ref = s.z - 0.0015;
    vec4 g00 = textureGather(shadow_map, i / size, ref), g10 = textureGather(shadow_map, (i + vec2(2.0, 0.0)) / size, ref),
         g01 = textureGather(shadow_map, (i + vec2(0.0, 2.0)) / size, ref),
         g11 = textureGather(shadow_map, (i + vec2(2.0)) / size, ref);
    vec4 wx = vec4(1.0 - f.x, 1.0, 1.0, f.x), wy = vec4(1.0 - f.y, 1.0, 1.0, f.y);
    // Rows of the block (texels i - 1 .. i + 2), columns in the same order.
    vec4 r0 = vec4(g00.w, g00.z, g10.w, g10.z), r1 = vec4(g00.x, g00.y, g10.x, g10.y),
         r2 = vec4(g01.w, g01.z, g11.w, g11.z), r3 = vec4(g01.x, g01.y, g11.x, g11.y);
    return dot(wy, vec4(dot(wx, r0), dot(wx, r1), dot(wx, r2), dot(wx, r3))) / 9.0;
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
