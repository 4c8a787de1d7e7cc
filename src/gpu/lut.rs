//! The runner's own LUT for the `lut` method (SPEC §5.7): an N×1 texture, texel i = exact F
//! at c = (i + ½)/N per channel (rgb; alpha 1), encoded as `rgba16float` (half float: the
//! smallest float format every adapter can filter linearly; `rgba32float` filtering is an
//! optional feature). Read in the shader with u = c, v = ½, linear filter, clamp-to-edge.
//!
//! MERGE: use bake:: — the bake module owns LUT textures and their encodings; replace
//! `texels` with its 1D row for one material and keep `upload`.

// MERGE: use bake:: (texels at (i + ½)/N from fresnel::exact, rgba16float) once bake is merged.

use half::f16;

use super::context::Gpu;
use crate::fresnel;
use crate::spectrum::ChannelIndex;

pub const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// The cosθ of texel `i` of `size`: its centre (i + ½)/size.
pub fn texel_cos(i: usize, size: usize) -> f64 {
    (i as f64 + 0.5) / size as f64
}

/// F at the texel centres, red, green, blue, alpha = 1, in f64 → f32.
pub fn texels(channels: &ChannelIndex, size: usize) -> Vec<[f32; 4]> {
    (0..size)
        .map(|i| {
            let c = texel_cos(i, size);
            let f = channels.map(|index| fresnel::exact(index.n, index.k, c) as f32);
            [f[0], f[1], f[2], 1.0]
        })
        .collect()
}

/// The texels as the GPU stores them (rounded to half floats), back in f32.
pub fn quantised(texels: &[[f32; 4]]) -> Vec<[f32; 4]> {
    texels.iter().map(|t| t.map(|x| f16::from_f32(x).to_f32())).collect()
}

/// Upload texels as an N×1 `rgba16float` texture.
pub fn upload(gpu: &Gpu, texels: &[[f32; 4]], label: &str) -> wgpu::Texture {
    let size = wgpu::Extent3d { width: texels.len() as u32, height: 1, depth_or_array_layers: 1 };
    let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size,
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: FORMAT,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    let halves: Vec<u16> = texels.iter().flat_map(|t| t.map(|x| f16::from_f32(x).to_bits())).collect();
    gpu.queue.write_texture(
        wgpu::TexelCopyTextureInfo { texture: &texture, mip_level: 0, origin: wgpu::Origin3d::ZERO, aspect: wgpu::TextureAspect::All },
        bytemuck::cast_slice(&halves),
        wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(8 * texels.len() as u32), rows_per_image: Some(1) },
        size,
    );
    texture
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::Index;

    #[test]
    fn texels_sit_at_centres() {
        let water = [Index::new(1.333, 0.0); 3];
        let t = texels(&water, 4);
        assert_eq!(t.len(), 4);
        assert!((t[3][0] as f64 - fresnel::exact(1.333, 0.0, 0.875)).abs() < 1e-7);
        assert_eq!(t[0][3], 1.0);
    }
}
