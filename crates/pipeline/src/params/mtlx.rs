//! `materials.mtlx`: a MaterialX 1.39 document with five materials per page, each one
//! parameterisation of the page's engine parameters (the node definitions are MaterialX's
//! standard libraries: `bxdf/open_pbr_surface.mtlx`, `bxdf/standard_surface.mtlx`,
//! `pbrlib/pbrlib_defs.mtlx`), every one with the page's export roughness:
//!
//! - `<id>_openpbr`: `open_pbr_surface` by the page's appearance — metals: base_color = F0,
//!   base_metalness = 1, specular_color = F82 tint; transparent: base_metalness = 0,
//!   specular_ior = n_d, transmission_weight = 1, and the dispersion's Abbe number where the
//!   page has one; tinted: also transmission_color at transmission_depth (the volume's
//!   colour); opaque dielectrics as metals: an opaque absorber reflects like a conductor
//!   (no light comes back out of its volume), and base_color = F0 keeps its F0 with k's
//!   share ((n − 1)² + k²)/((n + 1)² + k²) in every channel, which specular_ior = n_d
//!   alone loses. Colours are clamped to [0, 1], their UI range (an attenuation colour to
//!   [10⁻⁶, 1], `appearance::MIN_TRANSMITTANCE`).
//! - `<id>_standard_surface`: Autodesk `standard_surface` with `base` 1 (its default 0.8
//!   would darken metals by a fifth): metals through Gulbrandsen's reflectivity and edge
//!   tint (base_color, specular_color), which its metal Fresnel is (opaque dielectrics too);
//!   transmissive dielectrics as OpenPBR.
//! - `<id>_conductor`: `conductor_bsdf` with the fitted per-channel (n, k) — the channel's
//!   own (n, k) where the fit ended on its search box.
//! - `<id>_artistic`: `artistic_ior` (Gulbrandsen r, g) feeding a `conductor_bsdf`.
//! - `<id>_generalized_schlick`: `generalized_schlick_bsdf` (color0 = F0, color82,
//!   color90 = 1, exponent), color0 clamped to [0, 1] and color82 recomputed for the
//!   clamped color0 so that the model still meets the spectral curve at μ̄ = 1/7.
//!
//! The BSDF nodes take roughness as GGX α = r² in both directions. Each BSDF becomes a
//! surface shader through the `surface` node. Names are the page id with every character
//! other than A–Z, a–z, 0–9 and _ replaced by _, prefixed `nk_` (a second page with the
//! same name gets `_2`, `_3`, …); `doc` holds the page id and its display name.

use std::collections::{HashMap, HashSet};
use std::fmt::Write as _;

use super::caveats::Caveat;
use super::models::GeneralizedSchlick;
use super::page::EngineParams;
use crate::ingest::KeptPage;
use nklut_optics::appearance::Appearance;
use nklut_optics::spectrum::Kind;

/// What an export needs of a page.
#[derive(Clone, Debug)]
pub struct ExportPage<'a> {
    pub page: String,
    /// The short name a person reads ([`display_names`]).
    pub display: String,
    pub names: Vec<String>,
    pub kind: Kind,
    pub params: &'a EngineParams,
    /// The roughness every export gives this page ([`super::ExportSettings`]).
    pub roughness: f64,
    /// Where the data mislead ([`super::caveats`]).
    pub caveats: Vec<Caveat>,
}

impl<'a> ExportPage<'a> {
    /// `display` is the page's entry of [`display_names`] over the run's pages.
    pub fn new(page: &KeptPage, display: String, params: &'a EngineParams, caveats: Vec<Caveat>, settings: &super::ExportSettings) -> Self {
        Self {
            page: page.id(),
            display,
            names: page.names.clone(),
            kind: page.material.kind,
            params,
            roughness: settings.roughness(params.volume.appearance),
            caveats,
        }
    }

    /// "page id (display name)".
    pub fn title(&self) -> String {
        format!("{} ({})", self.page, self.display)
    }
}

/// The most characters of a display name.
pub const DISPLAY_CHARS: usize = 48;

/// A page's short name: on the `3d` shelf, whose pages are materials, the catalog's page
/// name ("Soda-lime glass - Green", "Gold (Au)"); elsewhere the book's name and the page
/// ("Au (Gold), Johnson"), the catalog's HTML made plain text ([`plain_text`]: "Al₂O₃").
/// Long synonym lists stay in the `synonyms` column; a name past [`DISPLAY_CHARS`] is cut
/// at a word and ends in "…".
pub fn display_name(page: &KeptPage) -> String {
    shortened(&full_name(page), DISPLAY_CHARS)
}

/// The uncut display name, plain text.
fn full_name(page: &KeptPage) -> String {
    let p = &page.page;
    plain_text(&if p.shelf == "3d" { p.page_name.clone() } else { format!("{}, {}", p.book_name, p.page) })
}

/// The catalog's names as plain text: `<sub>…</sub>` and `<sup>…</sup>` become Unicode
/// subscripts and superscripts where Unicode has every character of the group (digits,
/// the signs `+ − = ( )` and the letters it has: "Al<sub>2</sub>O<sub>3</sub>" → "Al₂O₃",
/// "(C<sub>6</sub>H<sub>10</sub>O<sub>5</sub>)<sub>n</sub>" → "(C₆H₁₀O₅)ₙ"), else their
/// plain characters; every other tag is dropped, the five XML entities decoded, control
/// characters and runs of white space read as one space.
pub fn plain_text(html: &str) -> String {
    let mut out = String::with_capacity(html.len());
    let mut rest = html;
    while let Some(open) = rest.find('<') {
        out.push_str(&rest[..open]);
        let after = &rest[open..];
        let Some(close) = after.find('>') else {
            out.push_str(after);
            rest = "";
            break;
        };
        let tag = after[1..close].trim().to_ascii_lowercase();
        rest = &after[close + 1..];
        if tag == "sub" || tag == "sup" {
            let end_tag = format!("</{tag}>");
            let (inner, remainder) = match rest.to_ascii_lowercase().find(&end_tag) {
                Some(end) => (&rest[..end], &rest[end + end_tag.len()..]),
                None => (rest, ""),
            };
            let inner = plain_text(inner);
            let map = if tag == "sub" { subscript } else { superscript };
            let mapped: Option<String> = inner.chars().map(map).collect();
            out.push_str(&mapped.unwrap_or(inner));
            rest = remainder;
        }
    }
    out.push_str(rest);
    let decoded = out.replace("&lt;", "<").replace("&gt;", ">").replace("&quot;", "\"").replace("&apos;", "'").replace("&amp;", "&");
    decoded.split(|c: char| c.is_whitespace() || c.is_control()).filter(|w| !w.is_empty()).collect::<Vec<_>>().join(" ")
}

/// The Unicode subscript of `c`, where it has one.
fn subscript(c: char) -> Option<char> {
    Some(match c {
        '0'..='9' => char::from_u32(0x2080 + (c as u32 - '0' as u32))?,
        '+' => '₊',
        '-' | '−' => '₋',
        '=' => '₌',
        '(' => '₍',
        ')' => '₎',
        'a' => 'ₐ',
        'e' => 'ₑ',
        'o' => 'ₒ',
        'x' => 'ₓ',
        'h' => 'ₕ',
        'k' => 'ₖ',
        'l' => 'ₗ',
        'm' => 'ₘ',
        'n' => 'ₙ',
        'p' => 'ₚ',
        's' => 'ₛ',
        't' => 'ₜ',
        'i' => 'ᵢ',
        'r' => 'ᵣ',
        'u' => 'ᵤ',
        'v' => 'ᵥ',
        'j' => 'ⱼ',
        _ => return None,
    })
}

/// The Unicode superscript of `c`, where it has one.
fn superscript(c: char) -> Option<char> {
    Some(match c {
        '0' => '⁰',
        '1' => '¹',
        '2' => '²',
        '3' => '³',
        '4'..='9' => char::from_u32(0x2074 + (c as u32 - '4' as u32))?,
        '+' => '⁺',
        '-' | '−' => '⁻',
        '=' => '⁼',
        '(' => '⁽',
        ')' => '⁾',
        'n' => 'ⁿ',
        'i' => 'ⁱ',
        _ => return None,
    })
}

/// The display names of a run's pages, one distinct name per page, each at most
/// [`DISPLAY_CHARS`] characters: a name two pages share gains the book's name ("Mercury
/// (Hg), METALS" beside "Mercury (Hg), LIQUIDS"), the name cut to leave it room; one still
/// shared after that gains " #2", " #3", … in page order (the first keeps its name), so
/// that an engine's material list tells them apart.
pub fn display_names(pages: &[KeptPage]) -> Vec<String> {
    let full: Vec<String> = pages.iter().map(full_name).collect();
    let first: Vec<String> = full.iter().map(|name| shortened(name, DISPLAY_CHARS)).collect();
    let mut shared: HashMap<&str, usize> = HashMap::new();
    for name in &first {
        *shared.entry(name.as_str()).or_default() += 1;
    }
    let with_book: Vec<String> = pages
        .iter()
        .zip(&full)
        .zip(&first)
        .map(|((page, full), name)| {
            if shared[name.as_str()] > 1 {
                with_suffix(full, &format!(", {}", shortened(&plain_text(&page.page.book_name), DISPLAY_CHARS / 2)))
            } else {
                name.clone()
            }
        })
        .collect();
    let mut taken: HashSet<String> = HashSet::new();
    with_book
        .into_iter()
        .map(|name| {
            let mut candidate = name.clone();
            let mut counter = 1;
            while !taken.insert(candidate.clone()) {
                counter += 1;
                candidate = with_suffix(&name, &format!(" #{counter}"));
            }
            candidate
        })
        .collect()
}

/// `stem` + `suffix` within [`DISPLAY_CHARS`], the stem cut ([`shortened`]) to leave the
/// suffix its room.
fn with_suffix(stem: &str, suffix: &str) -> String {
    let room = DISPLAY_CHARS.saturating_sub(suffix.chars().count()).max(2);
    format!("{}{suffix}", shortened(stem, room))
}

/// `text` cut to at most `chars` characters at a word boundary, "…" marking the cut.
pub fn shortened(text: &str, chars: usize) -> String {
    if text.chars().count() <= chars {
        return text.to_string();
    }
    let mut out = String::new();
    for word in text.split_whitespace() {
        if out.chars().count() + word.chars().count() + 2 > chars {
            break;
        }
        if !out.is_empty() {
            out.push(' ');
        }
        out.push_str(word);
    }
    if out.is_empty() {
        out = text.chars().take(chars.saturating_sub(1)).collect();
    }
    out.push('…');
    out
}

/// `nk_` + the page id with every character outside [A-Za-z0-9_] replaced by `_`; a name
/// longer than [`crate::output::MAX_STEM_BYTES`] is cut and ends in `_` and a hash of the
/// whole ([`crate::output::bounded_stem`]), so that it still names a file.
pub fn valid_name(page: &str) -> String {
    let body: String = page.chars().map(|c| if c.is_ascii_alphanumeric() || c == '_' { c } else { '_' }).collect();
    crate::output::bounded_stem(&format!("nk_{body}"), '_').into_owned()
}

/// One distinct name per page, in order (collisions get `_2`, `_3`, …).
pub fn unique_names<'p>(pages: impl IntoIterator<Item = &'p str>) -> Vec<String> {
    let mut taken = HashSet::new();
    pages
        .into_iter()
        .map(|page| {
            let base = valid_name(page);
            let mut name = base.clone();
            let mut counter = 1;
            while !taken.insert(name.clone()) {
                counter += 1;
                name = format!("{base}_{counter}");
            }
            name
        })
        .collect()
}

/// Text safe inside a double-quoted XML attribute ([`crate::escape::xml`]).
pub fn escape_attribute(text: &str) -> String {
    crate::escape::xml(text)
}

/// A MaterialX color3 value "r, g, b" (shortest round-trip decimals).
fn color3(rgb: [f64; 3]) -> String {
    format!("{}, {}, {}", rgb[0], rgb[1], rgb[2])
}

fn unit(rgb: [f64; 3]) -> [f64; 3] {
    rgb.map(|v| v.clamp(0.0, 1.0))
}

/// Builds the document text.
struct Writer {
    text: String,
}

impl Writer {
    fn node(&mut self, category: &str, name: &str, kind: &str, inputs: &[(&str, &str, String)]) {
        let _ = writeln!(self.text, "  <{category} name=\"{name}\" type=\"{kind}\">");
        for (input, input_type, value) in inputs {
            let _ = writeln!(self.text, "    <input name=\"{input}\" type=\"{input_type}\" value=\"{value}\" />");
        }
        let _ = writeln!(self.text, "  </{category}>");
    }

    /// A `surface` shader around `bsdf`, and its material.
    fn material_from_bsdf(&mut self, name: &str, bsdf: &str, doc: &str) {
        let _ = writeln!(self.text, "  <surface name=\"{name}_shader\" type=\"surfaceshader\">");
        let _ = writeln!(self.text, "    <input name=\"bsdf\" type=\"BSDF\" nodename=\"{bsdf}\" />");
        let _ = writeln!(self.text, "  </surface>");
        self.material(name, &format!("{name}_shader"), doc);
    }

    fn material(&mut self, name: &str, shader: &str, doc: &str) {
        let _ = writeln!(self.text, "  <surfacematerial name=\"{name}\" type=\"material\" doc=\"{}\">", escape_attribute(doc));
        let _ = writeln!(self.text, "    <input name=\"surfaceshader\" type=\"surfaceshader\" nodename=\"{shader}\" />");
        let _ = writeln!(self.text, "  </surfacematerial>");
    }
}

/// A scalar perceptual roughness as the (anisotropic) GGX α that MaterialX's BSDF nodes
/// take: α = r², in both directions (what its `roughness_anisotropy` node gives at
/// anisotropy 0).
fn alpha(roughness: f64) -> String {
    let a = roughness * roughness;
    format!("{a}, {a}")
}

/// The OpenPBR inputs of a page by its appearance (docs/engine-integration.md).
pub fn openpbr_inputs(page: &ExportPage) -> Vec<(&'static str, &'static str, String)> {
    let p = page.params;
    let mut inputs: Vec<(&str, &str, String)> = vec![("specular_roughness", "float", page.roughness.to_string())];
    let ior = p.dielectric.map(|d| d.n_d.max(1.0));
    match p.volume.appearance {
        // An opaque absorber reflects like a conductor: the metal path keeps its F0 (k's
        // share included) per channel, which specular_ior = n_d alone would lose.
        Appearance::Metal | Appearance::Opaque => {
            inputs.push(("base_weight", "float", "1".into()));
            inputs.push(("base_color", "color3", color3(unit(p.f0))));
            inputs.push(("base_metalness", "float", "1".into()));
            inputs.push(("specular_color", "color3", color3(unit(p.f82.map(|f| f.tint)))));
        }
        Appearance::Transparent | Appearance::Tinted => {
            inputs.push(("base_metalness", "float", "0".into()));
            if let Some(ior) = ior {
                inputs.push(("specular_ior", "float", ior.to_string()));
            }
            inputs.push(("transmission_weight", "float", "1".into()));
            if let Some(attenuation) = p.volume.attenuation {
                inputs.push(("transmission_color", "color3", color3(attenuation.exported_colour())));
                inputs.push(("transmission_depth", "float", attenuation.distance_m.to_string()));
            }
            if let Some(abbe) = p.dielectric.and_then(|d| d.abbe) {
                inputs.push(("transmission_dispersion_scale", "float", "1".into()));
                inputs.push(("transmission_dispersion_abbe_number", "float", abbe.to_string()));
            }
        }
    }
    inputs
}

/// The five materials of one page.
fn page_materials(w: &mut Writer, name: &str, page: &ExportPage) {
    let p = page.params;
    let title = page.title();
    let openpbr = format!("{name}_openpbr");
    w.node("open_pbr_surface", &format!("{openpbr}_shader"), "surfaceshader", &openpbr_inputs(page));
    w.material(
        &openpbr,
        &format!("{openpbr}_shader"),
        &format!(
            "{title}: OpenPBR by its appearance ({}): F0 and F82 tint, or n_d, transmission and its colour",
            p.volume.appearance.name()
        ),
    );

    // Autodesk Standard Surface: its metal Fresnel is Gulbrandsen's, base_color the
    // reflectivity and specular_color the edge tint; `base` at 1 (its default 0.8 darkens).
    let standard = format!("{name}_standard_surface");
    let mut inputs: Vec<(&str, &str, String)> =
        vec![("base", "float", "1".into()), ("specular_roughness", "float", page.roughness.to_string())];
    match p.volume.appearance {
        Appearance::Metal | Appearance::Opaque => {
            inputs.push(("metalness", "float", "1".into()));
            inputs.push(("base_color", "color3", color3(p.gulbrandsen.map(|g| g.r))));
            inputs.push(("specular_color", "color3", color3(p.gulbrandsen.map(|g| g.g))));
        }
        Appearance::Transparent | Appearance::Tinted => {
            inputs.push(("metalness", "float", "0".into()));
            if let Some(d) = p.dielectric {
                inputs.push(("specular_IOR", "float", d.n_d.max(1.0).to_string()));
            }
            inputs.push(("transmission", "float", "1".into()));
            if let Some(attenuation) = p.volume.attenuation {
                inputs.push(("transmission_color", "color3", color3(attenuation.exported_colour())));
                inputs.push(("transmission_depth", "float", attenuation.distance_m.to_string()));
            }
        }
    }
    w.node("standard_surface", &format!("{standard}_shader"), "surfaceshader", &inputs);
    w.material(
        &standard,
        &format!("{standard}_shader"),
        &format!("{title}: Autodesk Standard Surface (base 1; metals through Gulbrandsen's reflectivity and edge tint)"),
    );

    let conductor = format!("{name}_conductor");
    w.node(
        "conductor_bsdf",
        &format!("{conductor}_bsdf"),
        "BSDF",
        &[
            ("ior", "color3", color3(p.exported_index().map(|i| i.n))),
            ("extinction", "color3", color3(p.exported_index().map(|i| i.k))),
            ("roughness", "vector2", alpha(page.roughness)),
        ],
    );
    w.material_from_bsdf(
        &conductor,
        &format!("{conductor}_bsdf"),
        &format!(
            "{title}: conductor_bsdf with the fitted per-channel (n, k) (the channel's own (n, k) where the fit ended on its search box)"
        ),
    );

    let artistic = format!("{name}_artistic");
    w.node(
        "artistic_ior",
        &format!("{artistic}_ior"),
        "multioutput",
        &[("reflectivity", "color3", color3(p.gulbrandsen.map(|g| g.r))), ("edge_color", "color3", color3(p.gulbrandsen.map(|g| g.g)))],
    );
    let _ = writeln!(w.text, "  <conductor_bsdf name=\"{artistic}_bsdf\" type=\"BSDF\">");
    for output in ["ior", "extinction"] {
        let _ = writeln!(w.text, "    <input name=\"{output}\" type=\"color3\" nodename=\"{artistic}_ior\" output=\"{output}\" />");
    }
    let _ = writeln!(w.text, "    <input name=\"roughness\" type=\"vector2\" value=\"{}\" />", alpha(page.roughness));
    let _ = writeln!(w.text, "  </conductor_bsdf>");
    w.material_from_bsdf(
        &artistic,
        &format!("{artistic}_bsdf"),
        &format!("{title}: Gulbrandsen reflectivity and edge tint through artistic_ior"),
    );

    let schlick = format!("{name}_generalized_schlick");
    // color0 clamped to [0, 1] like every exported colour; color82 follows it so that the
    // model still meets the spectral curve at μ̄ (the table's color82 is for the unclamped F0).
    let fitted = &p.generalized_schlick;
    let g = &GeneralizedSchlick::through_edge(unit(fitted.color0), p.reference_at_edge, fitted.exponent);
    w.node(
        "generalized_schlick_bsdf",
        &format!("{schlick}_bsdf"),
        "BSDF",
        &[
            ("color0", "color3", color3(g.color0)),
            ("color82", "color3", color3(g.color82)),
            ("color90", "color3", color3(g.color90)),
            ("exponent", "float", g.exponent.to_string()),
            ("roughness", "vector2", alpha(page.roughness)),
        ],
    );
    w.material_from_bsdf(
        &schlick,
        &format!("{schlick}_bsdf"),
        &format!("{title}: Hoffman generalized Schlick fitted to the spectral curve"),
    );
}

/// The whole document, pages in the given order.
pub fn document(pages: &[ExportPage]) -> String {
    let mut w = Writer { text: String::new() };
    w.text.push_str("<?xml version=\"1.0\"?>\n");
    w.text.push_str("<materialx version=\"1.39\" colorspace=\"lin_rec709\">\n");
    let names = unique_names(pages.iter().map(|p| p.page.as_str()));
    for (page, name) in pages.iter().zip(&names) {
        page_materials(&mut w, name, page);
    }
    w.text.push_str("</materialx>\n");
    w.text
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_valid_and_distinct() {
        let names = unique_names(["3d/metals/gold", "main/Au/Johnson", "3d/metals:gold", "a b/é"]);
        assert_eq!(names, ["nk_3d_metals_gold", "nk_main_Au_Johnson", "nk_3d_metals_gold_2", "nk_a_b__"]);
    }

    #[test]
    fn catalog_html_becomes_plain_text() {
        assert_eq!(plain_text("Al<sub>2</sub>O<sub>3</sub> (Aluminium oxide)"), "Al₂O₃ (Aluminium oxide)");
        assert_eq!(plain_text("(C<sub>6</sub>H<sub>10</sub>O<sub>5</sub>)<sub>n</sub>"), "(C₆H₁₀O₅)ₙ");
        assert_eq!(plain_text("Ga<sub>1-x</sub>Al<sub>x</sub>As"), "Ga₁₋ₓAlₓAs");
        // A group Unicode cannot write keeps its plain characters.
        assert_eq!(plain_text("Si<sub>0.5</sub>Ge<sup>2+</sup> <i>bulk</i>"), "Si0.5Ge²⁺ bulk");
        assert_eq!(plain_text("a &amp; b\n\t c <b"), "a & b c <b");
        assert_eq!(plain_text("x<sub>12"), "x₁₂");
    }

    #[test]
    fn shortened_names_fit_and_keep_their_suffix() {
        let long = "Polyvinylpyrrolidone thin film, spin-coated on silicon, annealed at 120 C";
        let cut = with_suffix(long, ", ORGANIC MATERIALS");
        assert!(cut.chars().count() <= DISPLAY_CHARS && cut.ends_with("…, ORGANIC MATERIALS"), "{cut}");
        assert_eq!(shortened("abc", 3), "abc");
        assert_eq!(shortened("abcdef", 3), "ab…");
    }

    #[test]
    fn attributes_are_escaped() {
        assert_eq!(escape_attribute("a<b & \"c\"\n'd'>"), "a&lt;b &amp; &quot;c&quot; &apos;d&apos;&gt;");
    }
}
