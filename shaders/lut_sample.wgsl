// nklut Fresnel LUT sampling (see docs/engine-integration.md and luts/manifest.json).
//
// `lut` holds one row per page (an atlas), or a single row (a strip): texel i of the
// N texels of a row holds F(cos_theta) at its centre cos_theta = (i + 0.5) / N, channels
// R G B = red, green, blue Fresnel reflectance. Bind it with a sampler that filters
// linearly (mag and min, no mipmaps) and clamps to edge in u and v; use an -srgb texture
// format for the unorm8-srgb files so that the sampler returns linear F.
// Sampling at u = cos_theta, v = (row + 0.5) / rows then reproduces the LUT model exactly.
fn nklut_fresnel_lut(lut: texture_2d<f32>, lut_sampler: sampler, cos_theta: f32, row: u32) -> vec3<f32> {
    let rows = f32(textureDimensions(lut, 0).y);
    let uv = vec2<f32>(clamp(cos_theta, 0.0, 1.0), (f32(row) + 0.5) / rows);
    return textureSampleLevel(lut, lut_sampler, uv, 0.0).rgb;
}
