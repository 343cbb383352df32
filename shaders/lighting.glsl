// vergence — sun, sky and fog shared by the G-buffer and the sky.

vec3 sky_radiance(vec3 dir)
{
    float h = dir.y;
    vec3 up = mix(u.sky_horizon.rgb, u.sky_zenith.rgb, pow(clamp(h, 0.0, 1.0), 0.6));
    vec3 down = mix(u.sky_horizon.rgb, u.ground_color.rgb * 1.6, clamp(-h * 4.0, 0.0, 1.0));
    vec3 c = h >= 0.0 ? up : down;
    // A soft glow and a small disc where the sun is.
    float s = max(dot(dir, u.sun_dir.xyz), 0.0);
    c += u.sun_color.rgb * (0.05 * pow(s, 8.0) + 0.6 * smoothstep(0.9995, 0.9998, s));
    return c;
}

vec3 apply_fog(vec3 c, vec3 dir, float dist)
{
    float f = 1.0 - exp(-dist * u.sky_zenith.w);
    return mix(c, sky_radiance(normalize(vec3(dir.x, max(dir.y, 0.02), dir.z))) * 0.9, f);
}

// Filmic curve (Narkowicz's ACES fit) then the sRGB attachment encodes.
vec3 tonemap(vec3 c)
{
    c *= u.sky_horizon.w;
    return clamp((c * (2.51 * c + 0.03)) / (c * (2.43 * c + 0.59) + 0.14), 0.0, 1.0);
}

#include "lighting_srgb.glsl"
