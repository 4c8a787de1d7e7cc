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
use nklut_optics::appearance::{Appearance, Attenuation};
use nklut_optics::color::srgb::hex_swatch;

/// ((n − 1)/(n + 1))², a dielectric's F0.
fn fresnel_f0(n: f64) -> f64 {
    ((n - 1.0) / (n + 1.0)).powi(2)
}

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
        "caveats": page.caveats.iter().map(|c| json!({ "code": c.code, "text": c.text })).collect::<Vec<_>>(),
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

/// The most F0 a dielectric's Specular of Unreal and Godot gives (F0 = 0.08 · Specular,
/// Specular in [0, 1]).
pub const SPECULAR_008_MAX_F0: f64 = 0.08;
/// three.js' documented `ior` range of `MeshPhysicalMaterial` (three r187,
/// src/materials/MeshPhysicalMaterial.js: "from 1.0 to 2.333").
pub const THREE_IOR_RANGE: (f64, f64) = (1.0, 2.333);
/// The thickness the blocks give a refractive object (m): the 5 cm the exports' spheres
/// measure and the tinted class is judged at.
pub const OBJECT_THICKNESS_M: f64 = 0.05;
/// Significant digits of the blocks' distances, densities and coefficients: a relative
/// rounding error of at most 5·10⁻⁶ (half a unit in the sixth digit).
pub const SIGNIFICANT_DIGITS: usize = 6;

/// `x` with [`SIGNIFICANT_DIGITS`] significant digits, as plain decimals between 10⁻³ and
/// 10⁶ and in exponent notation (`3.64123e-4`, valid JavaScript, GLSL, Python and C)
/// outside; trailing zeros dropped. Never prints a non-zero number as 0.
pub fn significant(x: f64) -> String {
    if !x.is_finite() || x == 0.0 {
        return format!("{x}");
    }
    let exponent = x.abs().log10().floor() as i32;
    if (-3..6).contains(&exponent) {
        let decimals = (SIGNIFICANT_DIGITS as i32 - 1 - exponent).max(0) as usize;
        let text = format!("{x:.decimals$}");
        if text.contains('.') {
            text.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            text
        }
    } else {
        let text = format!("{x:.prec$e}", prec = SIGNIFICANT_DIGITS - 1);
        let (mantissa, exp) = text.split_once('e').unwrap_or((&text, "0"));
        let mantissa = if mantissa.contains('.') { mantissa.trim_end_matches('0').trim_end_matches('.') } else { mantissa };
        format!("{mantissa}e{exp}")
    }
}

/// Three numbers with [`significant`] digits, "(a, b, c)".
fn triple_significant(v: [f64; 3]) -> String {
    format!("({}, {}, {})", significant(v[0]), significant(v[1]), significant(v[2]))
}

/// `F0/0.08`, the Specular of Unreal and Godot (their F0 = 0.08 · Specular), clamped to the
/// field's [0, 1] with a note where the page's F0 is above what the field gives.
fn specular_008(f0: f64) -> String {
    let s = f0 / SPECULAR_008_MAX_F0;
    if s > 1.0 {
        format!("1 (the field's largest, F0 0.08; this page's F0 {f0:.4} is above it: the reflection is weaker than the material's)")
    } else {
        format!("{:.4}", s.max(0.0))
    }
}

/// What a transmissive page's volume passes through a piece [`OBJECT_THICKNESS_M`] thick:
/// c^(x/D) of the exported attenuation colour, white without attenuation.
fn through_object(page: &ExportPage) -> [f64; 3] {
    page.params.volume.attenuation.map_or([1.0; 3], |a| a.transmittance(OBJECT_THICKNESS_M))
}

/// The line saying why an opaque dielectric takes the metal path.
const OPAQUE_NOTE: &str = "an opaque absorber reflects like a conductor (no light comes back out of its volume): metallic 1 with F0 as the colour keeps its F0, k's share included, in every channel";

/// What every tool's block reads of a page, derived once.
#[derive(Clone, Copy)]
struct Facts {
    r: f64,
    f0: [f64; 3],
    f0_mean: f64,
    tint: [f64; 3],
    ior: Option<f64>,
    abbe: Option<f64>,
    attenuation: Option<Attenuation>,
    appearance: Appearance,
    /// What a piece [`OBJECT_THICKNESS_M`] thick passes.
    seen: [f64; 3],
}

impl Facts {
    fn of(page: &ExportPage) -> Self {
        let p = page.params;
        let f0 = p.f0;
        Facts {
            r: page.roughness,
            f0,
            f0_mean: (f0[0] + f0[1] + f0[2]) / 3.0,
            tint: p.f82.map(|f| f.tint),
            ior: p.dielectric.map(|d| d.n_d.max(1.0)),
            abbe: p.dielectric.and_then(|d| d.abbe),
            attenuation: p.volume.attenuation,
            appearance: p.volume.appearance,
            seen: through_object(page),
        }
    }
}

/// The opaque note of a tool whose dielectric Specular field is F0/0.08 (Unreal's
/// `Specular`, Godot's `metallic_specular`): what the field would give instead.
fn opaque_specular_note(field: &str, f0_mean: f64) -> String {
    format!("Note: {OPAQUE_NOTE} ({field} = F0/0.08 = {:.4} would give one grey F0, and at most 0.08)\n", f0_mean / SPECULAR_008_MAX_F0)
}

/// "label: n_d" and a line break, empty for a page without a refractive index.
fn ior_line(ior: Option<f64>, label: &str) -> String {
    ior.map_or(String::new(), |ior| format!("{label}: {ior:.4}\n"))
}

/// One tool's block of the page ([`TOOLS`] names the tools).
fn block(tool: &str, page: &ExportPage) -> String {
    let facts = Facts::of(page);
    match tool {
        "blender" => blender(facts),
        "unreal" => unreal(facts),
        "unity_hdrp" => unity_hdrp(facts),
        "threejs" => threejs(facts),
        "filament" => filament(facts),
        "godot" => godot(facts),
        "openpbr" => openpbr_inputs(page).into_iter().map(|(input, _, value)| format!("{input}: {value}\n")).collect(),
        "gltf" => {
            let (material, _) = super::gltf::material(page);
            serde_json::to_string_pretty(&material).unwrap_or_default() + "\n"
        }
        _ => String::new(),
    }
}

/// Blender's Principled BSDF fields.
fn blender(facts: Facts) -> String {
    let Facts { r, f0, tint, ior, attenuation, appearance, seen, .. } = facts;
    match appearance {
        Appearance::Metal | Appearance::Opaque => {
            let mut text = format!(
                "Base Color: {} (linear {})\nMetallic: 1\nRoughness: {r}\nSpecular Tint: {} (linear {}; Blender 4's F82 edge tint of metals)\n",
                hex_swatch(f0),
                triple(f0, true),
                hex_swatch(tint),
                triple(tint, true)
            );
            if appearance == Appearance::Opaque {
                text.push_str(&format!("Note: {OPAQUE_NOTE}\n"));
            }
            text
        }
        Appearance::Transparent | Appearance::Tinted => {
            let mut text = format!("Base Color: #ffffff\nMetallic: 0\nRoughness: {r}\n{}Transmission Weight: 1\n", ior_line(ior, "IOR"));
            if let Some(a) = attenuation {
                let v = a.volume_absorption();
                text.push_str(&format!(
                    "Volume: Volume Absorption node into the Material Output's Volume, Color {} (linear {}), Density {} (per scene unit, metres: the node absorbs (1 − Color)·Density, so Density = the largest absorption coefficient −ln(attenuation colour)/{} m and Color = 1 − coefficient/Density; a {} m piece then passes linear {})\n",
                    hex_swatch(v.colour),
                    triple_significant(v.colour),
                    significant(v.density),
                    significant(a.distance_m),
                    OBJECT_THICKNESS_M,
                    triple(seen, true)
                ));
            }
            text
        }
    }
}

/// Unreal's Default Lit (and Thin Translucent) fields.
fn unreal(facts: Facts) -> String {
    let Facts { r, f0, f0_mean, ior, appearance, seen, .. } = facts;
    match appearance {
        Appearance::Metal | Appearance::Opaque => {
            let mut text = format!("Base Color: linear {} (hex field {})\nMetallic: 1\nRoughness: {r}\n", triple(f0, true), hex_swatch(f0));
            if appearance == Appearance::Opaque {
                text.push_str(&opaque_specular_note("Specular", f0_mean));
            }
            text
        }
        Appearance::Transparent | Appearance::Tinted => format!(
            "Blend Mode: Translucent; Shading Model: Thin Translucent; Lighting Mode: Surface ForwardShading\nBase Color: (0, 0, 0)\nMetallic: 0\nRoughness: {r}\nSpecular: {}\nOpacity: 1 (the surface coverage; what passes is the Transmittance Color)\nThin Translucent Material output, Transmittance Color: linear {} (what a {} m piece passes at normal view)\n{}",
            specular_008(f0_mean),
            triple(seen, true),
            OBJECT_THICKNESS_M,
            ior_line(ior, "Refraction (Refraction Method: Index of Refraction)")
        ),
    }
}

/// Unity HDRP Lit's fields.
fn unity_hdrp(facts: Facts) -> String {
    let Facts { r, f0, ior, attenuation, appearance, .. } = facts;
    match appearance {
        Appearance::Metal => {
            format!(
                "Material Type: Standard\nBase Map colour: {} (linear {})\nMetallic: 1\nSmoothness: {:.3}\n",
                hex_swatch(f0),
                triple(f0, true),
                1.0 - r
            )
        }
        Appearance::Transparent | Appearance::Tinted => {
            let mut text = format!(
                "Surface Type: Transparent; Refraction Model: Sphere\nMetallic: 0\nSmoothness: {:.3}\n{}",
                1.0 - r,
                ior_line(ior, "Index Of Refraction")
            );
            if let Some(a) = attenuation {
                let colour = a.exported_colour();
                text.push_str(&format!(
                    "Transmittance Color: {} (linear {})\nAbsorption Distance: {} (m)\n",
                    hex_swatch(colour),
                    triple_significant(colour),
                    significant(a.distance_m)
                ));
            }
            text
        }
        Appearance::Opaque => format!(
            "Material Type: Specular Color\nBase Map colour: #000000\nSpecular Color: {} (linear {})\nSmoothness: {:.3}\n",
            hex_swatch(f0),
            triple(f0, true),
            1.0 - r
        ),
    }
}

/// A three.js `MeshPhysicalMaterial` constructor.
fn threejs(facts: Facts) -> String {
    let Facts { r, f0, ior, abbe, attenuation, appearance, .. } = facts;
    let colour = |name: &str, rgb: [f64; 3]| {
        let [a, b, c] = rgb.map(|v| v.clamp(0.0, 1.0));
        format!("  {name}: new THREE.Color().setRGB({a:.4}, {b:.4}, {c:.4}, THREE.LinearSRGBColorSpace),\n")
    };
    let mut text = String::from("new THREE.MeshPhysicalMaterial({\n");
    match appearance {
        Appearance::Metal | Appearance::Opaque => {
            text.push_str(&colour("color", f0));
            text.push_str(&format!("  metalness: 1,\n  roughness: {r},\n"));
            if appearance == Appearance::Opaque {
                text.push_str(&format!("  // {OPAQUE_NOTE}\n"));
            }
        }
        Appearance::Transparent | Appearance::Tinted => {
            text.push_str(&format!(
                "  metalness: 0,\n  roughness: {r},\n  transmission: 1,\n  thickness: {OBJECT_THICKNESS_M}, // in the mesh's own units, which three.js scales by the object's world scale: {OBJECT_THICKNESS_M} for a {} cm object modelled in metres at scale 1\n",
                OBJECT_THICKNESS_M * 100.0
            ));
            if let Some(n) = ior {
                let shown = n.min(THREE_IOR_RANGE.1);
                text.push_str(&format!("  ior: {shown:.4},\n"));
                if n > THREE_IOR_RANGE.1 {
                    // F0 of n_d kept through specularColor: three.js takes
                    // min(F0(ior) · specularColor, 1).
                    let scale = fresnel_f0(n) / fresnel_f0(shown);
                    text.push_str(&format!(
                        "  specularColor: new THREE.Color().setRGB({scale:.4}, {scale:.4}, {scale:.4}, THREE.LinearSRGBColorSpace), // n_d {n:.4} is above three.js' ior range (1 to {}): its F0 {:.4} kept as F0({}) × specularColor\n",
                        THREE_IOR_RANGE.1,
                        fresnel_f0(n),
                        THREE_IOR_RANGE.1
                    ));
                }
            }
            if let Some(a) = attenuation {
                let [x, y, z] = a.exported_colour();
                text.push_str(&format!(
                    "  attenuationColor: new THREE.Color().setRGB({}, {}, {}, THREE.LinearSRGBColorSpace),\n",
                    significant(x),
                    significant(y),
                    significant(z)
                ));
                text.push_str(&format!(
                    "  attenuationDistance: {}, // world units (metres), {SIGNIFICANT_DIGITS} significant digits\n",
                    significant(a.distance_m)
                ));
            }
            if let Some(abbe) = abbe {
                text.push_str(&format!("  dispersion: {:.4}, // 20 / Abbe number {abbe:.2}\n", 20.0 / abbe));
            }
        }
    }
    text.push_str("});\n");
    text
}

/// Filament's lit material properties.
fn filament(facts: Facts) -> String {
    let Facts { r, f0, f0_mean, ior, attenuation, appearance, seen, .. } = facts;
    match appearance {
        Appearance::Metal | Appearance::Opaque => {
            let mut text = format!("baseColor: {}\nmetallic: 1.0\nroughness: {r}\n", triple(f0, true));
            if appearance == Appearance::Opaque {
                text.push_str(&format!("Note: {OPAQUE_NOTE} (reflectance = √(F0/0.16) = {:.4} would give one grey F0, and at most 0.16 with reflectance in its [0, 1])\n", (f0_mean.max(0.0) / 0.16).sqrt()));
            }
            text
        }
        Appearance::Transparent | Appearance::Tinted => {
            let mut text = format!(
                "material {{ blending: opaque; refractionMode: screenspace; refractionType: solid }} (refractionMode cubemap refracts the environment only)\nbaseColor: (1, 1, 1)\nmetallic: 0.0\nroughness: {r}\ntransmission: 1.0\n{}thickness: {OBJECT_THICKNESS_M} (world units, metres: the object's thickness along the normal)\n",
                ior_line(ior, "ior")
            );
            if let Some(a) = attenuation {
                text.push_str(&format!(
                    "absorption: {} (per metre: −ln(attenuation colour)/{} m; e^(−absorption·thickness) passes linear {})\n",
                    triple_significant(a.coefficients_per_m()),
                    significant(a.distance_m),
                    triple(seen, true)
                ));
            }
            text
        }
    }
}

/// Godot's `StandardMaterial3D` properties.
fn godot(facts: Facts) -> String {
    let Facts { r, f0, f0_mean, appearance, seen, .. } = facts;
    match appearance {
        Appearance::Metal | Appearance::Opaque => {
            let mut text = format!("albedo_color: Color(\"{}\")\nmetallic: 1.0\nroughness: {r}\n", hex_swatch(f0));
            if appearance == Appearance::Opaque {
                text.push_str(&opaque_specular_note("metallic_specular", f0_mean));
            }
            text
        }
        Appearance::Transparent | Appearance::Tinted => format!(
            "transparency: alpha; albedo_color: Color(\"{}\", 0.1) (the colour a {} m piece passes)\nmetallic: 0.0\nroughness: {r}\nmetallic_specular: {}\nrefraction_enabled: true (Godot's refraction is a screen-space offset, not an IOR)\n",
            hex_swatch(seen),
            OBJECT_THICKNESS_M,
            specular_008(f0_mean)
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn significant_digits_never_print_a_small_number_as_zero() {
        assert_eq!(significant(0.000364123456), "3.64123e-4");
        assert_eq!(significant(0.0112457), "0.0112457");
        assert_eq!(significant(1.0), "1");
        assert_eq!(significant(2.5e-9), "2.5e-9");
        assert_eq!(significant(123456.7), "123457");
        assert_eq!(significant(2.0e7), "2e7");
        assert_eq!(significant(0.0), "0");
        // The relative error of 6 significant digits is at most 5e-6.
        for x in [3.64123456e-4, 9.99999e-5, 1.23456789, 0.0100000049, 7.7777777e3] {
            let back: f64 = significant(x).parse().unwrap();
            assert!((back / x - 1.0).abs() <= 5e-6, "{x} → {}", significant(x));
        }
    }
}
