//! The runner's texture for the `lut` method (SPEC §5.7): an N×1 `rgba16float` texture
//! (half float: the smallest float format every adapter can filter linearly;
//! `rgba32float` filtering is an optional feature), rgb = the red, green, blue channel of
//! `fresnel::Lut::bake(LutSpec::new(N, Encoding::F16), exact)` — texel i = exact F at
//! c = (i + ½)/N, already rounded to half floats — and alpha 1. Read in the shader with
//! u = c, v = ½, linear filter, clamp-to-edge.

use half::f16;

use super::context::Gpu;
use nklut_optics::fresnel::{Encoding, Lut, LutSpec, Prepared};

pub const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// The encoding of [`FORMAT`] in the fresnel module's terms.
pub const ENCODING: Encoding = Encoding::F16;

/// The texels of `size` as the GPU stores them (exactly representable as half floats):
/// red, green, blue, alpha = 1.
pub fn texels(prepared: &[Prepared; 3], size: usize) -> Vec<[f32; 4]> {
    let [r, g, b] = [0, 1, 2].map(|c| &prepared[c]).map(|p| Lut::bake(LutSpec::new(size, ENCODING), |c| p.exact.reflectance(c)).texels_f32);
    r.iter().zip(&g).zip(&b).map(|((&r, &g), &b)| [r, g, b, 1.0]).collect()
}

/// Upload texels as an N×1 `rgba16float` texture.
pub fn upload(gpu: &Gpu, texels: &[[f32; 4]], label: &str) -> wgpu::Texture {
    upload_rows(gpu, texels, 1, label)
}

/// Upload `rows` rows of texels (row-major, one curve per row: an atlas) as an
/// `rgba16float` texture, read like the shipped atlases (`shaders/lut_sample.wgsl`).
pub fn upload_rows(gpu: &Gpu, texels: &[[f32; 4]], rows: u32, label: &str) -> wgpu::Texture {
    let width = texels.len() as u32 / rows.max(1);
    let size = wgpu::Extent3d { width, height: rows, depth_or_array_layers: 1 };
    let texture = super::render::texture_2d(gpu, label, size, FORMAT, wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST);
    let halves = half_bits(texels);
    gpu.queue.write_texture(
        wgpu::TexelCopyTextureInfo { texture: &texture, mip_level: 0, origin: wgpu::Origin3d::ZERO, aspect: wgpu::TextureAspect::All },
        bytemuck::cast_slice(&halves),
        wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(8 * width), rows_per_image: Some(rows) },
        size,
    );
    texture
}

/// The half-float bits of RGBA texels as [`FORMAT`] stores them, row-major (what
/// [`upload_rows`] writes and the browser bench embeds).
pub fn half_bits(texels: &[[f32; 4]]) -> Vec<u16> {
    texels.iter().flat_map(|t| t.map(|x| f16::from_f32(x).to_bits())).collect()
}

/// The sampler every LUT is read with (SPEC §5.7): linear filtering, clamp-to-edge.
pub fn sampler(gpu: &Gpu) -> wgpu::Sampler {
    gpu.device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("lut linear clamp"),
        address_mode_u: wgpu::AddressMode::ClampToEdge,
        address_mode_v: wgpu::AddressMode::ClampToEdge,
        address_mode_w: wgpu::AddressMode::ClampToEdge,
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        ..Default::default()
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use nklut_optics::fresnel;
    use nklut_optics::spectrum::Index;

    #[test]
    fn texels_sit_at_centres_and_are_stored_exactly() {
        let water = [Index::new(1.333, 0.0); 3].map(Prepared::new);
        let t = texels(&water, 4);
        assert_eq!(t.len(), 4);
        let expected = fresnel::exact(1.333, 0.0, nklut_optics::encoding::texel_cos(3, 4));
        assert!((t[3][0] as f64 - expected).abs() <= expected * 1e-3);
        assert_eq!(t[0][3], 1.0);
        for x in t.iter().flatten() {
            assert_eq!(f16::from_f32(*x).to_f32(), *x, "the upload must not round again");
        }
    }
}
