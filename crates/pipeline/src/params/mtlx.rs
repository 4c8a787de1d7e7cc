//! `materials.mtlx`: a MaterialX 1.39 document with four materials per page, each one
//! parameterisation of the page's engine parameters (the node definitions are MaterialX's
//! standard libraries: `bxdf/open_pbr_surface.mtlx`, `pbrlib/pbrlib_defs.mtlx`):
//!
//! - `<id>_openpbr`: `open_pbr_surface` — conductors: base_color = F0, base_metalness = 1,
//!   specular_color = F82 tint; dielectrics: base_metalness = 0, specular_ior = n_d,
//!   transmission_weight = 1 (a clear dielectric: the data say nothing of volume colour).
//!   base_color and specular_color are clamped to [0, 1], their UI range.
//! - `<id>_conductor`: `conductor_bsdf` with the fitted per-channel (n, k).
//! - `<id>_artistic`: `artistic_ior` (Gulbrandsen r, g) feeding a `conductor_bsdf`.
//! - `<id>_generalized_schlick`: `generalized_schlick_bsdf` (color0 = F0, color82,
//!   color90 = 1, exponent), values unclamped so the model is the one of the table.
//!
//! Each BSDF becomes a surface shader through the `surface` node. Names are the page id
//! with every character other than A–Z, a–z, 0–9 and _ replaced by _, prefixed `nk_`
//! (a second page with the same name gets `_2`, `_3`, …); `doc` holds the page id and names.

use std::collections::HashSet;
use std::fmt::Write as _;

use super::page::EngineParams;
use crate::ingest::KeptPage;
use nklut_optics::spectrum::Kind;

/// What an export needs of a page.
#[derive(Clone, Debug)]
pub struct ExportPage<'a> {
    pub page: String,
    pub names: Vec<String>,
    pub kind: Kind,
    pub params: &'a EngineParams,
}

impl<'a> ExportPage<'a> {
    pub fn new(page: &KeptPage, params: &'a EngineParams) -> Self {
        Self { page: page.id(), names: page.names.clone(), kind: page.material.kind, params }
    }

    /// "page id (names)".
    pub fn title(&self) -> String {
        if self.names.is_empty() {
            self.page.clone()
        } else {
            format!("{} ({})", self.page, self.names.join("; "))
        }
    }
}

/// `nk_` + the page id with every character outside [A-Za-z0-9_] replaced by `_`.
pub fn valid_name(page: &str) -> String {
    let body: String = page.chars().map(|c| if c.is_ascii_alphanumeric() || c == '_' { c } else { '_' }).collect();
    format!("nk_{body}")
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

/// Text safe inside a double-quoted XML attribute.
pub fn escape_attribute(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c if (c as u32) < 0x20 => out.push(' '),
            c => out.push(c),
        }
    }
    out
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

/// The four materials of one page.
fn page_materials(w: &mut Writer, name: &str, page: &ExportPage) {
    let p = page.params;
    let title = page.title();
    let openpbr = format!("{name}_openpbr");
    let mut inputs: Vec<(&str, &str, String)> = Vec::new();
    match (page.kind, p.dielectric) {
        (Kind::Dielectric, Some(d)) => {
            inputs.push(("base_metalness", "float", "0".into()));
            inputs.push(("specular_ior", "float", d.n_d.to_string()));
            inputs.push(("transmission_weight", "float", "1".into()));
        }
        _ => {
            inputs.push(("base_color", "color3", color3(unit(p.f0))));
            inputs.push(("base_metalness", "float", "1".into()));
            inputs.push(("specular_color", "color3", color3(unit(p.f82.map(|f| f.tint)))));
        }
    }
    w.node("open_pbr_surface", &format!("{openpbr}_shader"), "surfaceshader", &inputs);
    w.material(&openpbr, &format!("{openpbr}_shader"), &format!("{title}: OpenPBR from F0 and F82 tint (dielectrics: n_d)"));

    let conductor = format!("{name}_conductor");
    w.node(
        "conductor_bsdf",
        &format!("{conductor}_bsdf"),
        "BSDF",
        &[("ior", "color3", color3(p.fitted.map(|f| f.index.n))), ("extinction", "color3", color3(p.fitted.map(|f| f.index.k)))],
    );
    w.material_from_bsdf(&conductor, &format!("{conductor}_bsdf"), &format!("{title}: conductor_bsdf with the fitted per-channel (n, k)"));

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
    let _ = writeln!(w.text, "  </conductor_bsdf>");
    w.material_from_bsdf(
        &artistic,
        &format!("{artistic}_bsdf"),
        &format!("{title}: Gulbrandsen reflectivity and edge tint through artistic_ior"),
    );

    let schlick = format!("{name}_generalized_schlick");
    let g = &p.generalized_schlick;
    w.node(
        "generalized_schlick_bsdf",
        &format!("{schlick}_bsdf"),
        "BSDF",
        &[
            ("color0", "color3", color3(g.color0)),
            ("color82", "color3", color3(g.color82)),
            ("color90", "color3", color3(g.color90)),
            ("exponent", "float", g.exponent.to_string()),
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
    fn attributes_are_escaped() {
        assert_eq!(escape_attribute("a<b & \"c\"\n'd'>"), "a&lt;b &amp; &quot;c&quot; &apos;d&apos;&gt;");
    }
}
