"""nklut Fresnel lookup textures in Blender (4.x/5.x, Cycles and EEVEE): a node group that
samples one row of a `luts/` atlas by the facing ratio, and materials that drive their
specular reflection (and refraction) with it.

The sampling convention (docs/engine-integration.md, luts/manifest.json -> sampling): row r of
an atlas of `rows` rows holds F(cos theta) of one material, texel i of N at cos theta =
(i + 0.5)/N; sampled with linear filtering and clamp-to-edge at u = cos theta and v at the
row's centre it returns the LUT model whose error the manifest states. In Blender:

- cos theta = clamp(dot(Normal, Incoming), 0, 1) from the Geometry node (Incoming points to
  the viewer): the facing ratio, exact, where the Layer Weight node's Facing output is
  1 - |N.I| only at Blend 0.5;
- Image Texture: interpolation Linear, extension EXTEND (clamp to edge), no mipmaps;
- Blender's image origin is the bottom-left corner, so the file's first row (the atlas's row
  0) is at the top: v = 1 - (row + 0.5)/rows, for PNG and EXR alike;
- colour space Non-Color for the linear encodings (unorm8, unorm16, f16, f32), sRGB for
  unorm8-srgb. Blender reads 16-bit PNGs and EXRs as float.

`material()` makes a material whose specular colour is F_LUT(n.v): a Glossy BSDF (no Fresnel
of its own in Blender 4/5) coloured by the row, plus for dielectrics a Refraction BSDF
coloured 1 - F (it has none either), so reflected and transmitted light share F as the
Fresnel equations do. The Principled BSDF's Fresnel is fixed (F82-tinted Schlick, from Base
Color and Specular Tint), so a LUT cannot replace it there; this mix is the route.

Usage (Blender's Python console or `blender --python`):

    import json, sys; sys.path.append("/path/to/nklut/clients/blender")
    import nklut_lut
    manifest = json.load(open("luts/manifest.json"))
    mat = nklut_lut.material_for_page(manifest, "luts", "3d/metals/gold", encoding="f16", roughness=0.05)
    bpy.context.object.data.materials.append(mat)

`tests/clients/check_blender_lut.py` (run by `make test-blender`) renders spheres with
`fresnel_debug_material` and compares every pixel against the exact Fresnel curve.
"""

import os

import bpy

GROUP_NAME = "nklut Fresnel LUT"

# Colour space of each encoding's image (Blender's names).
COLOR_SPACES = {
    "unorm8": "Non-Color",
    "unorm8-srgb": "sRGB",
    "unorm16": "Non-Color",
    "f16": "Non-Color",
    "f32": "Non-Color",
}


def texture_set(manifest, source, encoding):
    """The manifest's texture set for a source and an encoding."""
    for t in manifest["textures"]:
        if t["source"] == source and t["encoding"] == encoding:
            if not t.get("atlas"):
                raise ValueError(f"{source}/{encoding} was baked without the atlas layout")
            return t
    raise ValueError(f"the manifest has no texture set {source}/{encoding}")


def load_atlas(path, encoding):
    """The atlas image, with the colour space of its encoding."""
    if encoding not in COLOR_SPACES:
        raise ValueError(f"unknown encoding {encoding}")
    image = bpy.data.images.load(os.path.abspath(path), check_existing=True)
    image.colorspace_settings.name = COLOR_SPACES[encoding]
    image.alpha_mode = "NONE"
    return image


def row_v(row, rows):
    """v of a row's centre in Blender (origin bottom-left; the file's first row on top)."""
    return 1.0 - (row + 0.5) / rows


def fresnel_group(image):
    """The node group of one atlas: input V (the row's v), outputs Fresnel (colour) and Cos.

    Made once per image (named after it)."""
    name = f"{GROUP_NAME}: {image.name}"
    group = bpy.data.node_groups.get(name)
    if group is not None:
        return group
    group = bpy.data.node_groups.new(name, "ShaderNodeTree")
    group.interface.new_socket("V", in_out="INPUT", socket_type="NodeSocketFloat")
    group.interface.new_socket("Fresnel", in_out="OUTPUT", socket_type="NodeSocketColor")
    group.interface.new_socket("Cos", in_out="OUTPUT", socket_type="NodeSocketFloat")
    nodes, links = group.nodes, group.links
    inputs = nodes.new("NodeGroupInput")
    outputs = nodes.new("NodeGroupOutput")
    geometry = nodes.new("ShaderNodeNewGeometry")
    dot = nodes.new("ShaderNodeVectorMath")
    dot.operation = "DOT_PRODUCT"
    links.new(geometry.outputs["Normal"], dot.inputs[0])
    links.new(geometry.outputs["Incoming"], dot.inputs[1])
    cos = nodes.new("ShaderNodeMath")
    cos.operation = "ADD"  # dot + 0, clamped to [0, 1]
    cos.use_clamp = True
    cos.inputs[1].default_value = 0.0
    links.new(dot.outputs["Value"], cos.inputs[0])
    uv = nodes.new("ShaderNodeCombineXYZ")
    links.new(cos.outputs[0], uv.inputs["X"])
    links.new(inputs.outputs["V"], uv.inputs["Y"])
    texture = nodes.new("ShaderNodeTexImage")
    texture.image = image
    texture.interpolation = "Linear"
    texture.extension = "EXTEND"
    texture.projection = "FLAT"
    links.new(uv.outputs["Vector"], texture.inputs["Vector"])
    links.new(texture.outputs["Color"], outputs.inputs["Fresnel"])
    links.new(cos.outputs[0], outputs.inputs["Cos"])
    return group


def _group_node(material, image, row, rows):
    node = material.node_tree.nodes.new("ShaderNodeGroup")
    node.node_tree = fresnel_group(image)
    node.inputs["V"].default_value = row_v(row, rows)
    return node


def material(name, image, row, rows, kind, ior=1.5, roughness=0.0):
    """A material whose reflection is Glossy(colour F_LUT(n.v)); dielectrics add
    Refraction(colour 1 - F, IOR `ior`)."""
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    nodes.clear()
    out = nodes.new("ShaderNodeOutputMaterial")
    lut = _group_node(mat, image, row, rows)
    glossy = nodes.new("ShaderNodeBsdfGlossy")
    glossy.distribution = "GGX"
    glossy.inputs["Roughness"].default_value = roughness
    links.new(lut.outputs["Fresnel"], glossy.inputs["Color"])
    if kind == "conductor":
        links.new(glossy.outputs["BSDF"], out.inputs["Surface"])
        return mat
    one_minus = nodes.new("ShaderNodeMix")
    one_minus.data_type = "RGBA"
    one_minus.blend_type = "SUBTRACT"
    one_minus.inputs["Factor"].default_value = 1.0
    one_minus.inputs["A"].default_value = (1.0, 1.0, 1.0, 1.0)
    links.new(lut.outputs["Fresnel"], one_minus.inputs["B"])
    refraction = nodes.new("ShaderNodeBsdfRefraction")
    refraction.inputs["IOR"].default_value = ior
    refraction.inputs["Roughness"].default_value = roughness
    links.new(one_minus.outputs["Result"], refraction.inputs["Color"])
    add = nodes.new("ShaderNodeAddShader")
    links.new(glossy.outputs["BSDF"], add.inputs[0])
    links.new(refraction.outputs["BSDF"], add.inputs[1])
    links.new(add.outputs["Shader"], out.inputs["Surface"])
    return mat


def material_for_page(manifest, luts_dir, page, source="three-channel", encoding="f16", roughness=0.0):
    """`material()` for a page of a bake: the atlas of source/encoding under `luts_dir`."""
    t = texture_set(manifest, source, encoding)
    row = next((r for r in t["rows"] if r["page"] == page), None)
    if row is None:
        raise ValueError(f"no row {page} in {source}/{encoding}")
    image = load_atlas(os.path.join(luts_dir, t["atlas"]["file"]), encoding)
    n = row["index_three_channel"][1]["n"]
    return material(f"nklut {page}", image, row["row"], t["atlas"]["height"], row["kind"], ior=n, roughness=roughness)


def fresnel_debug_material(name, image, row, rows, output):
    """Emission of the node group's `output` ("Fresnel", or "Cos" as grey): renders the
    Fresnel term (or cos theta) itself, for checks."""
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    nodes.clear()
    out = nodes.new("ShaderNodeOutputMaterial")
    lut = _group_node(mat, image, row, rows)
    emission = nodes.new("ShaderNodeEmission")
    emission.inputs["Strength"].default_value = 1.0
    links.new(lut.outputs[output], emission.inputs["Color"])
    links.new(emission.outputs["Emission"], out.inputs["Surface"])
    return mat
