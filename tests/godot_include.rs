//! clients/godot/nklut_lut.gdshaderinc against Godot 4's shading language as its reference
//! ("Shading language" and "Shader preprocessor" pages of the Godot 4 documentation): only
//! the preprocessor directives Godot 4 has, no `shader_type` (an include may not hold one),
//! sampler hints from Godot 4's list, Godot types, calls only to Godot built-ins or functions
//! the file defines, no GLSL-only names (`gl_*`, `in`/`out` globals, `#version`), and the
//! sampling convention of docs/engine-integration.md. No Godot binary runs here (Debian ships
//! only Godot 3, whose shading language has neither includes nor a preprocessor); the body is
//! compiled and run as GLSL ES 3.00 in Chromium by tests/three_lut.rs.

use std::collections::BTreeSet;

const INCLUDE: &str = include_str!("../clients/godot/nklut_lut.gdshaderinc");

/// Godot 4's sampler hints (uniform hints for `sampler2D`).
const SAMPLER_HINTS: [&str; 20] = [
    "source_color",
    "hint_normal",
    "hint_default_white",
    "hint_default_black",
    "hint_default_transparent",
    "hint_anisotropy",
    "hint_roughness_r",
    "hint_roughness_g",
    "hint_roughness_b",
    "hint_roughness_a",
    "hint_roughness_normal",
    "hint_roughness_gray",
    "filter_nearest",
    "filter_linear",
    "filter_nearest_mipmap",
    "filter_linear_mipmap",
    "filter_nearest_mipmap_anisotropic",
    "filter_linear_mipmap_anisotropic",
    "repeat_enable",
    "repeat_disable",
];

/// Godot 4's types and the built-in functions this include may call.
const TYPES: [&str; 12] = ["void", "bool", "int", "uint", "float", "vec2", "vec3", "vec4", "ivec2", "ivec3", "mat3", "sampler2D"];
const BUILTINS: [&str; 11] = ["clamp", "dot", "float", "int", "textureSize", "textureLod", "texture", "vec2", "vec3", "vec4", "ivec2"];

/// The file without comments.
fn code() -> String {
    INCLUDE.lines().map(|l| l.split("//").next().unwrap()).collect::<Vec<_>>().join("\n")
}

fn identifiers(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut current = String::new();
    for ch in text.chars().chain([' ']) {
        if ch.is_ascii_alphanumeric() || ch == '_' {
            current.push(ch);
        } else if !current.is_empty() {
            if !current.chars().next().unwrap().is_ascii_digit() {
                out.push(current.clone());
            }
            current.clear();
        }
    }
    out
}

#[test]
fn only_godot_4_directives_and_no_shader_type() {
    let code = code();
    for line in code.lines().map(str::trim).filter(|l| l.starts_with('#')) {
        let directive = line.split_whitespace().next().unwrap();
        assert!(["#ifdef", "#ifndef", "#else", "#endif", "#define", "#include", "#if", "#elif", "#undef"].contains(&directive), "{line}");
    }
    assert!(!code.contains("shader_type"), "an include may not declare shader_type");
    assert!(!code.contains("#version") && !code.contains("gl_"), "GLSL-only names");
}

#[test]
fn uniforms_use_godot_types_and_sampler_hints() {
    let code = code();
    let uniforms: Vec<&str> = code.lines().map(str::trim).filter(|l| l.starts_with("uniform ")).collect();
    assert_eq!(uniforms.len(), 3, "{uniforms:?}");
    for line in uniforms {
        let declaration = line.trim_end_matches(';');
        let (head, hints) = declaration.split_once(':').unwrap_or((declaration, ""));
        let words: Vec<&str> = head.split('=').next().unwrap().split_whitespace().collect();
        assert!(TYPES.contains(&words[1]), "{line}: type {}", words[1]);
        for hint in hints.split(',').map(str::trim).filter(|h| !h.is_empty()) {
            assert!(words[1] == "sampler2D" && SAMPLER_HINTS.contains(&hint), "{line}: hint {hint}");
        }
        if words[1] == "sampler2D" {
            // The convention: linear filtering, clamp-to-edge (Godot: repeat_disable).
            assert!(hints.contains("filter_linear") && hints.contains("repeat_disable") && !hints.contains("mipmap"), "{line}");
        }
    }
    // The sRGB variant decodes to linear F; the linear one must not.
    let srgb = code.split("#else").next().unwrap();
    assert!(srgb.contains("source_color") && !code.split("#else").nth(1).unwrap().contains("source_color"));
}

#[test]
fn calls_only_godot_builtins_or_its_own_functions_and_keeps_the_convention() {
    let code = code();
    let tokens = identifiers(&code);
    let defined: BTreeSet<String> = tokens
        .windows(3)
        .filter(|w| TYPES.contains(&w[0].as_str()) && code.contains(&format!("{}(", w[1])))
        .map(|w| w[1].clone())
        .collect();
    assert!(defined.contains("nklut_fresnel"), "{defined:?}");
    let bytes = code.as_bytes();
    let mut at = 0;
    for name in &tokens {
        let position = code[at..].find(name.as_str()).unwrap() + at;
        at = position + name.len();
        if bytes.get(at) == Some(&b'(') {
            assert!(BUILTINS.contains(&name.as_str()) || defined.contains(name), "{name} is neither a Godot built-in nor defined here");
        }
    }
    for convention in ["clamp(cos_theta, 0.0, 1.0)", "(float(nklut_row) + 0.5) / rows", "textureLod(nklut_lut, uv, 0.0)"] {
        assert!(code.contains(convention), "{convention}");
    }
}
