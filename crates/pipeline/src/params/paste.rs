//! Paste-in blocks: per page, `params/<name>.json` (`name` as in `materials.mtlx`) with the
//! colours as `[r, g, b]` triplets (linear) and as 8-bit sRGB hex strings, the scalars,
//! and one block of text per tool, ready to copy into its fields — Blender's Principled
//! BSDF, Unreal, Unity HDRP's Lit, three.js' `MeshPhysicalMaterial`, Filament, Godot,
//! OpenPBR and glTF. Each block follows the page's appearance and the export roughness,
//! and uses each tool's own parameterisation (Unreal's and Godot's Specular = F0/0.08,
//! Filament's reflectance = √(F0/0.16), Unity's smoothness = 1 − roughness), saying so
//! where a value leaves the field's range. The report shows the same blocks.

use serde_json::{json, Value};

use super::mtlx::{openpbr_inputs, ExportPage};
use nklut_optics::appearance::Appearance;
use nklut_optics::color::srgb::hex_swatch;

/// A linear colour as "(r, g, b)" with 4 decimals, clamped to [0, 1] where `unit`.
fn triple(rgb: [f64; 3], unit: bool) -> String {
    let v = rgb.map(|x| if unit { x.clamp(0.0, 1.0) } else { x });
    format!("({:.4}, {:.4}, {:.4})", v[0], v[1], v[2])
}

/// A colour as a paste-in JSON object: linear triplet and sRGB hex.
fn colour_json(rgb: [f64; 3]) -> Value {
    json!({ "linear": rgb, "hex": hex_swatch(rgb) })
}

/// The JSON of one page.
pub fn page_json(page: &ExportPage) -> Value {
    let p = page.params;
    let tint = p.f82.map(|f| f.tint);
    let attenuation = p.volume.attenuation.map(|a| json!({ "colour": colour_json(a.colour), "distance_m": a.distance_m }));
    let blocks: serde_json::Map<String, Value> =
        blocks(page).into_iter().map(|(tool, text)| (tool.to_string(), Value::String(text))).collect();
    json!({
        "page": page.page,
        "name": page.display,
        "synonyms": page.names,
        "kind": page.kind.as_str(),
        "appearance": p.volume.appearance.name(),
        "roughness": page.roughness,
        "f0": colour_json(p.f0),
        "f82_tint": colour_json(tint),
        "ior": p.dielectric.map(|d| d.n_d),
        "abbe": p.dielectric.and_then(|d| d.abbe),
        "attenuation": attenuation,
        "absorption_depth_m": p.volume.depths_m.map(|d| if d.is_finite() { Value::from(d) } else { Value::Null }),
        "conductor_index": { "n": p.exported_index().map(|i| i.n), "k": p.exported_index().map(|i| i.k) },
        "engines": blocks,
    })
}

/// The tools, in the order the report shows them, with their titles.
pub const TOOLS: [(&str, &str); 8] = [
    ("blender", "Blender 4/5 Principled BSDF"),
    ("unreal", "Unreal Engine (Default Lit)"),
    ("unity_hdrp", "Unity HDRP Lit"),
    ("threejs", "three.js MeshPhysicalMaterial"),
    ("filament", "Filament (lit material)"),
    ("godot", "Godot StandardMaterial3D"),
    ("openpbr", "OpenPBR Surface"),
    ("gltf", "glTF 2.0 material"),
];

/// Every tool's block of the page, in [`TOOLS`] order.
pub fn blocks(page: &ExportPage) -> Vec<(&'static str, String)> {
    TOOLS.iter().map(|&(tool, _)| (tool, block(tool, page))).collect()
}

/// `F0/0.08`, the Specular of Unreal and Godot (their F0 = 0.08 · Specular), with a note
/// where it leaves [0, 1].
fn specular_008(f0: f64) -> String {
    let s = f0 / 0.08;
    if s > 1.0 {
        format!("{s:.3} (above the field's 1: F0 {f0:.3} > 0.08; enter 1 or the value where the field takes it)")
    } else {
        format!("{s:.3}")
    }
}

fn block(tool: &str, page: &ExportPage) -> String {
    let p = page.params;
    let r = page.roughness;
    let f0 = p.f0;
    let f0_mean = (f0[0] + f0[1] + f0[2]) / 3.0;
    let tint = p.f82.map(|f| f.tint);
    let ior = p.dielectric.map(|d| d.n_d.max(1.0));
    let abbe = p.dielectric.and_then(|d| d.abbe);
    let attenuation = p.volume.attenuation;
    let appearance = p.volume.appearance;
    let ior_line = |label: &str| ior.map_or(String::new(), |ior| format!("{label}: {ior:.4}\n"));
    match tool {
        "blender" => match appearance {
            Appearance::Metal => format!(
                "Base Color: {} (linear {})\nMetallic: 1\nRoughness: {r}\nSpecular Tint: {} (linear {}; Blender 4's F82 edge tint of metals)\n",
                hex_swatch(f0),
                triple(f0, true),
                hex_swatch(tint),
                triple(tint, true)
            ),
            Appearance::Transparent | Appearance::Tinted => {
                let mut text = format!("Base Color: #ffffff\nMetallic: 0\nRoughness: {r}\n{}Transmission Weight: 1\n", ior_line("IOR"));
                if let Some(a) = attenuation {
                    text.push_str(&format!(
                        "Volume: Volume Absorption node into the Material Output's Volume, Color {} (linear {}), Density {:.4} (1/distance in scene units of metres; the colour white light takes after {:.4} m)\n",
                        hex_swatch(a.colour),
                        triple(a.colour, true),
                        1.0 / a.distance_m,
                        a.distance_m
                    ));
                }
                text
            }
            Appearance::Opaque => {
                let over_ior = f0.map(|v| v / ior.map_or(0.04, |n| ((n - 1.0) / (n + 1.0)).powi(2)));
                format!(
                    "Base Color: #000000 (no diffuse: light entering is absorbed)\nMetallic: 0\nRoughness: {r}\n{}Specular IOR Level: 0.5\nSpecular Tint: {} (linear {}: F0 over the F0 the IOR gives)\n",
                    ior_line("IOR"),
                    hex_swatch(over_ior),
                    triple(over_ior, false)
                )
            }
        },
        "unreal" => match appearance {
            Appearance::Metal => format!("Base Color: linear {} (hex field {})\nMetallic: 1\nRoughness: {r}\n", triple(f0, true), hex_swatch(f0)),
            Appearance::Transparent | Appearance::Tinted => format!(
                "Blend Mode: Translucent; Lighting Mode: Surface TranslucencyVolume\nBase Color: linear {}\nMetallic: 0\nRoughness: {r}\nSpecular: {}\n{}",
                triple(attenuation.map_or([1.0; 3], |a| a.colour), true),
                specular_008(f0_mean),
                ior_line("Refraction (Index of Refraction mode)")
            ),
            Appearance::Opaque => format!("Base Color: (0, 0, 0)\nMetallic: 0\nRoughness: {r}\nSpecular: {}\n", specular_008(f0_mean)),
        },
        "unity_hdrp" => match appearance {
            Appearance::Metal => {
                format!("Material Type: Standard\nBase Map colour: {} (linear {})\nMetallic: 1\nSmoothness: {:.3}\n", hex_swatch(f0), triple(f0, true), 1.0 - r)
            }
            Appearance::Transparent | Appearance::Tinted => {
                let mut text = format!("Surface Type: Transparent; Refraction Model: Sphere\nMetallic: 0\nSmoothness: {:.3}\n{}", 1.0 - r, ior_line("Index Of Refraction"));
                if let Some(a) = attenuation {
                    text.push_str(&format!("Transmittance Color: {} (linear {})\nAbsorption Distance: {:.4} (m)\n", hex_swatch(a.colour), triple(a.colour, true), a.distance_m));
                }
                text
            }
            Appearance::Opaque => format!(
                "Material Type: Specular Color\nBase Map colour: #000000\nSpecular Color: {} (linear {})\nSmoothness: {:.3}\n",
                hex_swatch(f0),
                triple(f0, true),
                1.0 - r
            ),
        },
        "threejs" => {
            let colour = |name: &str, rgb: [f64; 3]| {
                let [a, b, c] = rgb.map(|v| v.clamp(0.0, 1.0));
                format!("  {name}: new THREE.Color().setRGB({a:.4}, {b:.4}, {c:.4}, THREE.LinearSRGBColorSpace),\n")
            };
            let mut text = String::from("new THREE.MeshPhysicalMaterial({\n");
            match appearance {
                Appearance::Metal => {
                    text.push_str(&colour("color", f0));
                    text.push_str(&format!("  metalness: 1,\n  roughness: {r},\n"));
                }
                Appearance::Transparent | Appearance::Tinted => {
                    text.push_str(&format!("  metalness: 0,\n  roughness: {r},\n  transmission: 1,\n  thickness: 0.05, // the object's thickness (m)\n"));
                    if let Some(ior) = ior {
                        text.push_str(&format!("  ior: {ior:.4},\n"));
                    }
                    if let Some(a) = attenuation {
                        text.push_str(&colour("attenuationColor", a.colour));
                        text.push_str(&format!("  attenuationDistance: {:.4},\n", a.distance_m));
                    }
                    if let Some(abbe) = abbe {
                        text.push_str(&format!("  dispersion: {:.4}, // 20 / Abbe number {abbe:.2}\n", 20.0 / abbe));
                    }
                }
                Appearance::Opaque => {
                    text.push_str("  color: new THREE.Color(0, 0, 0),\n  metalness: 0,\n");
                    text.push_str(&format!("  roughness: {r},\n"));
                    if let Some(ior) = ior {
                        text.push_str(&format!("  ior: {ior:.4},\n"));
                    }
                    let from_ior = ior.map_or(0.04, |n| ((n - 1.0) / (n + 1.0)).powi(2));
                    let [a, b, c] = f0.map(|v| v / from_ior);
                    text.push_str(&format!("  specularColor: new THREE.Color().setRGB({a:.4}, {b:.4}, {c:.4}, THREE.LinearSRGBColorSpace), // F0 over the IOR's\n"));
                }
            }
            text.push_str("});\n");
            text
        }
        "filament" => match appearance {
            Appearance::Metal => format!("baseColor: {}\nmetallic: 1.0\nroughness: {r}\n", triple(f0, true)),
            Appearance::Transparent | Appearance::Tinted => {
                let mut text = format!("blending: opaque; refractionMode: solid; refractionType: solid\nbaseColor: (1, 1, 1)\nmetallic: 0.0\nroughness: {r}\ntransmission: 1.0\n{}", ior_line("ior"));
                if let Some(a) = attenuation {
                    let absorption = a.colour.map(|t| -t.max(1e-6).ln() / a.distance_m);
                    text.push_str(&format!("absorption: {} (−ln(transmittance colour) / distance, per metre)\n", triple(absorption, false)));
                }
                text
            }
            Appearance::Opaque => format!("baseColor: (0, 0, 0)\nmetallic: 0.0\nroughness: {r}\nreflectance: {:.4} (√(F0/0.16))\n", (f0_mean / 0.16).sqrt()),
        },
        "godot" => match appearance {
            Appearance::Metal => format!("albedo_color: Color(\"{}\")\nmetallic: 1.0\nroughness: {r}\n", hex_swatch(f0)),
            Appearance::Transparent | Appearance::Tinted => format!(
                "transparency: alpha; albedo_color: Color(\"{}\", 0.1)\nmetallic: 0.0\nroughness: {r}\nmetallic_specular: {}\nrefraction_enabled: true (Godot's refraction is a screen-space offset, not an IOR)\n",
                hex_swatch(attenuation.map_or([1.0; 3], |a| a.colour)),
                specular_008(f0_mean)
            ),
            Appearance::Opaque => format!("albedo_color: Color(\"#000000\")\nmetallic: 0.0\nroughness: {r}\nmetallic_specular: {}\n", specular_008(f0_mean)),
        },
        "openpbr" => openpbr_inputs(page).into_iter().map(|(input, _, value)| format!("{input}: {value}\n")).collect(),
        "gltf" => {
            let (material, _) = super::gltf::material(page);
            serde_json::to_string_pretty(&material).unwrap_or_default() + "\n"
        }
        _ => String::new(),
    }
}
