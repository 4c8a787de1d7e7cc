//! `materials.gltf` + `materials.bin`: a glTF 2.0 scene (Khronos glTF 2.0 specification)
//! with one sphere per page, 5 cm across (glTF's unit is the metre: a marble, the size the
//! tinted class is judged at), laid out on a grid in the x–y plane (y up, row-major in page
//! order), ready to drop into any glTF viewer. Node names are page ids, material names the
//! pages' short display names.
//!
//! Materials follow the page's appearance (`nklut_optics::appearance`), one roughness for
//! every material of a class ([`super::ExportSettings`], written in `asset.extras`):
//! - metals: baseColorFactor = F0 clamped to [0, 1] (linear), metallicFactor 1 — glTF's
//!   metal is Schlick with F0 = base colour; no ratified extension carries the F82 edge
//!   colour (the table's `schlick_*` errors say what leaving it out costs);
//! - transparent: metallicFactor 0, `KHR_materials_transmission` 1, `KHR_materials_ior`
//!   n_d (≥ 1), `KHR_materials_volume` thicknessFactor = the sphere's diameter (a solid
//!   that refracts, not a thin shell), `KHR_materials_dispersion` 20/V_d where the page
//!   has an Abbe number (the extension's definition);
//! - tinted: as transparent, with the volume's attenuationColor and attenuationDistance
//!   (the colour white light turns after that distance, spectrally; each channel clamped
//!   to [10⁻⁶, 1] so that the extension's −ln(c)/d stays finite);
//! - opaque dielectrics: no transmission, no diffuse (base colour black), the spectral F0
//!   as the specular colour (`KHR_materials_specular` specularColorFactor = F0 over the
//!   F0 the ior gives, so the two make F0).
//!
//! The sphere: RINGS × SEGMENTS UV sphere of radius 1 in its mesh (positions = normals),
//! scaled by its node; one triangle per segment at each pole (no degenerate triangles),
//! counter-clockwise seen from outside, 16-bit indices; every mesh shares its accessors.

use anyhow::{ensure, Result};
use serde_json::{json, Value};

use super::mtlx::ExportPage;
use nklut_optics::appearance::Appearance;

pub const RINGS: usize = 16;
pub const SEGMENTS: usize = 32;
/// The spheres' radius (m): 2.5 cm, a marble.
pub const RADIUS_M: f64 = 0.025;
/// Distance between sphere centres (m).
pub const SPACING: f64 = 2.5 * RADIUS_M;

/// The two files of the scene.
#[derive(Clone, Debug)]
pub struct GltfScene {
    pub json: Vec<u8>,
    pub bin: Vec<u8>,
}

/// The unit sphere: positions (= normals) and triangle indices.
pub struct Sphere {
    pub positions: Vec<[f32; 3]>,
    pub indices: Vec<u16>,
}

/// A UV sphere of radius 1 with `rings` latitude bands and `segments` longitude bands.
pub fn sphere(rings: usize, segments: usize) -> Sphere {
    let mut positions = Vec::with_capacity((rings + 1) * (segments + 1));
    for i in 0..=rings {
        let polar = std::f64::consts::PI * i as f64 / rings as f64;
        for j in 0..=segments {
            let azimuth = 2.0 * std::f64::consts::PI * j as f64 / segments as f64;
            let (x, y, z) = (polar.sin() * azimuth.cos(), polar.cos(), -polar.sin() * azimuth.sin());
            let length = (x * x + y * y + z * z).sqrt();
            positions.push([(x / length) as f32, (y / length) as f32, (z / length) as f32]);
        }
    }
    let vertex = |i: usize, j: usize| (i * (segments + 1) + j) as u16;
    let mut indices = Vec::new();
    for i in 0..rings {
        for j in 0..segments {
            let (a, b, c, d) = (vertex(i, j), vertex(i + 1, j), vertex(i + 1, j + 1), vertex(i, j + 1));
            if i != 0 {
                indices.extend([a, b, d]);
            }
            if i != rings - 1 {
                indices.extend([d, b, c]);
            }
        }
    }
    Sphere { positions, indices }
}

/// The glTF material of a page and the extensions it uses.
pub fn material(page: &ExportPage) -> (Value, Vec<&'static str>) {
    let p = page.params;
    let roughness = page.roughness;
    let ior = p.dielectric.map(|d| d.n_d.max(1.0));
    let mut extensions = serde_json::Map::new();
    let pbr = match p.volume.appearance {
        Appearance::Metal => {
            let [r, g, b] = p.f0.map(|v| v.clamp(0.0, 1.0));
            json!({ "baseColorFactor": [r, g, b, 1.0], "metallicFactor": 1.0, "roughnessFactor": roughness })
        }
        Appearance::Transparent | Appearance::Tinted => {
            if let Some(ior) = ior {
                extensions.insert("KHR_materials_ior".into(), json!({ "ior": ior }));
            }
            extensions.insert("KHR_materials_transmission".into(), json!({ "transmissionFactor": 1.0 }));
            let mut volume = json!({ "thicknessFactor": 2.0 });
            if let Some(attenuation) = p.volume.attenuation {
                volume["attenuationColor"] = json!(attenuation.exported_colour());
                volume["attenuationDistance"] = json!(attenuation.distance_m);
            }
            extensions.insert("KHR_materials_volume".into(), volume);
            if let Some(abbe) = p.dielectric.and_then(|d| d.abbe) {
                extensions.insert("KHR_materials_dispersion".into(), json!({ "dispersion": 20.0 / abbe }));
            }
            json!({ "baseColorFactor": [1.0, 1.0, 1.0, 1.0], "metallicFactor": 0.0, "roughnessFactor": roughness })
        }
        Appearance::Opaque => {
            let ior = ior.unwrap_or(1.5);
            extensions.insert("KHR_materials_ior".into(), json!({ "ior": ior }));
            let from_ior = ((ior - 1.0) / (ior + 1.0)).powi(2);
            extensions.insert("KHR_materials_specular".into(), json!({ "specularColorFactor": p.f0.map(|v| v.max(0.0) / from_ior) }));
            json!({ "baseColorFactor": [0.0, 0.0, 0.0, 1.0], "metallicFactor": 0.0, "roughnessFactor": roughness })
        }
    };
    let used: Vec<&'static str> =
        ["KHR_materials_dispersion", "KHR_materials_ior", "KHR_materials_specular", "KHR_materials_transmission", "KHR_materials_volume"]
            .into_iter()
            .filter(|e| extensions.contains_key(*e))
            .collect();
    let mut value = json!({ "name": page.display, "pbrMetallicRoughness": pbr });
    if !extensions.is_empty() {
        value["extensions"] = Value::Object(extensions);
    }
    (value, used)
}

/// The scene of `pages`; `bin_uri` is the buffer's file name next to the .gltf.
pub fn scene(pages: &[ExportPage], bin_uri: &str, settings: &super::ExportSettings) -> Result<GltfScene> {
    ensure!(!pages.is_empty(), "a glTF scene needs at least one material");
    let sphere = sphere(RINGS, SEGMENTS);
    let mut bin: Vec<u8> = Vec::new();
    for p in &sphere.positions {
        p.iter().for_each(|v| bin.extend(v.to_le_bytes()));
    }
    let vertex_bytes = bin.len();
    // Normals of a unit sphere centred at the origin are the positions.
    bin.extend_from_within(0..vertex_bytes);
    let index_offset = bin.len();
    sphere.indices.iter().for_each(|i| bin.extend(i.to_le_bytes()));
    let index_bytes = bin.len() - index_offset;
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let (min, max) = sphere
        .positions
        .iter()
        .fold(([f32::MAX; 3], [f32::MIN; 3]), |(lo, hi), p| ([0, 1, 2].map(|i| lo[i].min(p[i])), [0, 1, 2].map(|i| hi[i].max(p[i]))));
    let columns = (pages.len() as f64).sqrt().ceil() as usize;
    let mut used: Vec<&str> = Vec::new();
    let mut materials = Vec::new();
    for page in pages {
        let (value, extensions) = material(page);
        materials.push(value);
        for e in extensions {
            if !used.contains(&e) {
                used.push(e);
            }
        }
    }
    used.sort_unstable();
    let meshes: Vec<Value> = pages
        .iter()
        .enumerate()
        .map(|(i, page)| json!({ "name": page.display, "primitives": [{ "attributes": { "POSITION": 0, "NORMAL": 1 }, "indices": 2, "material": i }] }))
        .collect();
    let nodes: Vec<Value> = pages
        .iter()
        .enumerate()
        .map(|(i, page)| {
            let (row, column) = (i / columns, i % columns);
            json!({
                "name": page.page,
                "mesh": i,
                "translation": [column as f64 * SPACING, -(row as f64) * SPACING, 0.0],
                "scale": [RADIUS_M, RADIUS_M, RADIUS_M]
            })
        })
        .collect();
    let mut document = json!({
        "asset": {
            "version": "2.0",
            "generator": format!("nklut {} params", env!("CARGO_PKG_VERSION")),
            "extras": { "nklut": { "sphere_radius_m": RADIUS_M, "roughness": settings.describe() } }
        },
        "scene": 0,
        "scenes": [{ "name": "nklut materials", "nodes": (0..pages.len()).collect::<Vec<_>>() }],
        "nodes": nodes,
        "meshes": meshes,
        "materials": materials,
        "buffers": [{ "uri": bin_uri, "byteLength": bin.len() }],
        "bufferViews": [
            { "buffer": 0, "byteOffset": 0, "byteLength": vertex_bytes, "target": 34962 },
            { "buffer": 0, "byteOffset": vertex_bytes, "byteLength": vertex_bytes, "target": 34962 },
            { "buffer": 0, "byteOffset": index_offset, "byteLength": index_bytes, "target": 34963 }
        ],
        "accessors": [
            { "bufferView": 0, "componentType": 5126, "count": sphere.positions.len(), "type": "VEC3", "min": min, "max": max },
            { "bufferView": 1, "componentType": 5126, "count": sphere.positions.len(), "type": "VEC3" },
            { "bufferView": 2, "componentType": 5123, "count": sphere.indices.len(), "type": "SCALAR" }
        ]
    });
    if !used.is_empty() {
        document["extensionsUsed"] = json!(used);
    }
    let mut json = serde_json::to_vec_pretty(&document)?;
    json.push(b'\n');
    Ok(GltfScene { json, bin })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sphere_is_closed_unit_and_outward() {
        let s = sphere(RINGS, SEGMENTS);
        assert!(s.positions.iter().all(|p| ((p[0] as f64).powi(2) + (p[1] as f64).powi(2) + (p[2] as f64).powi(2) - 1.0).abs() < 1e-6));
        // Triangles: 2 per quad except one per segment at each pole.
        assert_eq!(s.indices.len(), 3 * (2 * RINGS * SEGMENTS - 2 * SEGMENTS));
        let mut area = 0.0;
        for t in s.indices.chunks(3) {
            let [a, b, c] = [0, 1, 2].map(|i| s.positions[t[i] as usize].map(f64::from));
            let (u, v) = ([0, 1, 2].map(|i| b[i] - a[i]), [0, 1, 2].map(|i| c[i] - a[i]));
            let normal = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
            let centre = [0, 1, 2].map(|i| a[i] + b[i] + c[i]);
            let length = (normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]).sqrt();
            assert!(length > 1e-6, "degenerate triangle {t:?}");
            assert!(normal[0] * centre[0] + normal[1] * centre[1] + normal[2] * centre[2] > 0.0, "inward triangle {t:?}");
            area += length / 2.0;
        }
        // A 16 x 32 UV sphere's area is a little under 4π.
        assert!(area < 4.0 * std::f64::consts::PI && area > 0.97 * 4.0 * std::f64::consts::PI, "{area}");
    }
}
