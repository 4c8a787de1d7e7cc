"""Import `nklut params`' materials.gltf with Blender's own glTF importer and check, per
page, what Blender ends up with against the page's row of engine_params.csv.

Blender runs as a Python module (PyPI `bpy`, pinned by `make test-blender`, which installs
it into .test-deps/blender-venv). The wheel is a few hundred MB (≈ 375 MB download, ≈ 1 GB
installed), so this check is optional: `make test` and CI do not run it.

Usage: .test-deps/blender-venv/bin/python check_blender.py DIR
DIR holds materials.gltf (+ materials.bin) and engine_params.csv of the same `params` run.

The scene is reset to an empty one, the file imported with `bpy.ops.import_scene.gltf`,
and every imported mesh object is matched to its page through the glTF node whose
translation puts the sphere where the object is, by name (node name = page id) or, should
Blender have changed the name (its length limit, a clash), as the one object there
(listed under "renamed"). Per page, on the Principled BSDF of the object's material (the
importer's node for pbrMetallicRoughness; its sockets have the same names in Blender 4.x
and 5.0: 'Transmission Weight', 'Specular Tint', 'Specular IOR Level'):

  every appearance: Base Color, Metallic, Roughness, IOR, Transmission Weight, Specular
      Tint and Specular IOR Level are constants (no texture or other node drives them);
      Roughness = export_roughness;
  metal:       Base Color = F0 (f0_linear_*) clamped to [0, 1]; Metallic 1; IOR 1.5 (the
               importer's default without KHR_materials_ior); Transmission 0; no volume;
  transparent: Base Color white; Metallic 0; IOR = n_d; Transmission 1; a Volume
               Absorption on the output's Volume socket with Color white and Density 0
               (no attenuation: 1 / +inf); Thickness of the 'glTF Material Output' group =
               the sphere's diameter in its mesh; screen-space refraction on (EEVEE);
  tinted:      as transparent, with Volume Absorption Color = attenuation_colour_* and
               Density = 1 / attenuation_distance_m (per metre: the scene's unit);
  opaque:      Base Color black; Metallic 0; IOR = n_d; Transmission 0; no volume;
               Specular Tint = F0 / F0(n_d) (KHR_materials_specular specularColorFactor);
  all but opaque: Specular Tint white; every appearance: Specular IOR Level 0.5.

Tolerance: 1e-4 (relative above 1): Blender stores float32.

What the glTF says and Blender has no place for is listed under "not_imported" (it does
not fail the check: it says what Blender keeps); what Blender keeps under another model
under "approximated".

Prints one JSON line: {"blender": version, "materials": N, "checked": {appearance: count},
"failures": [...], "renamed": [...], "not_imported": [...], "approximated": [...]}. Exit
status 0 when there are no failures, 1 when there are, 2 when DIR lacks a file.
"""
import csv
import json
import math
import os
import sys

import bpy

TOLERANCE = 1e-4
# The importer's IOR without KHR_materials_ior (io_scene_gltf2 io/com/constants.py
# GLTF_IOR, the glTF default).
GLTF_DEFAULT_IOR = 1.5
APPEARANCES = ("metal", "transparent", "tinted", "opaque")


def number(text):
    """A CSV cell as a float; None when empty."""
    return float(text) if text not in ("", None) else None


def rgb(row, prefix):
    values = [number(row[f"{prefix}_{c}"]) for c in "rgb"]
    return None if any(v is None for v in values) else values


def clamp01(values):
    return [min(max(v, 0.0), 1.0) for v in values]


def close(actual, expected):
    return abs(actual - expected) <= TOLERANCE * max(1.0, abs(expected))


def socket(node, name):
    """The input `name` of `node`, or None where this Blender has none."""
    return node.inputs[name] if name in node.inputs else None


def value(sock):
    v = sock.default_value
    try:
        return [float(x) for x in v]
    except TypeError:
        return float(v)


def f0_of_ior(ior):
    return ((ior - 1.0) / (ior + 1.0)) ** 2


def gltf_to_blender(translation):
    """glTF is y up, Blender z up: the importer maps (x, y, z) to (x, -z, y)."""
    x, y, z = (list(translation) + [0.0, 0.0, 0.0])[:3]
    return (x, -z, y)


class Checker:
    def __init__(self):
        self.failures = []

    def fail(self, page, what):
        self.failures.append(f"{page}: {what}")

    def scalar(self, page, what, actual, expected):
        if actual is None:
            self.fail(page, f"{what}: absent in Blender")
        elif not close(actual, expected):
            self.fail(page, f"{what} = {actual:.6g}, expected {expected:.6g}")

    def colour(self, page, what, actual, expected):
        if actual is None:
            self.fail(page, f"{what}: absent in Blender")
            return
        # Colour sockets hold RGBA; glTF factors and the table are RGB.
        if any(not close(a, e) for a, e in zip(actual[:3], expected)):
            shown = ", ".join(f"{a:.6g}" for a in actual[:3])
            wanted = ", ".join(f"{e:.6g}" for e in expected)
            self.fail(page, f"{what} = ({shown}), expected ({wanted})")


def load(directory):
    gltf_path = os.path.join(directory, "materials.gltf")
    csv_path = os.path.join(directory, "engine_params.csv")
    for path in (gltf_path, csv_path):
        if not os.path.isfile(path):
            print(json.dumps({"blender": bpy.app.version_string, "failures": [f"{path}: missing"]}))
            sys.exit(2)
    with open(gltf_path, encoding="utf-8") as f:
        gltf = json.load(f)
    with open(csv_path, newline="", encoding="utf-8") as f:
        rows = {row["page"]: row for row in csv.DictReader(f)}
    return gltf_path, gltf, rows


def match_objects(gltf, check):
    """page id -> (Blender object, glTF node), and the pages whose object Blender renamed.

    Each glTF node puts its sphere at its own place on the grid, and the importer keeps the
    node's translation: the object at that place with the node's name (= the page id) is
    the page's. Where Blender changed the name (its 255-byte limit, a clash it settles
    with .001), the one object at the node's place is."""
    nodes = [n for n in gltf.get("nodes", []) if "mesh" in n]
    objects = [o for o in bpy.data.objects if o.type == "MESH"]
    matched, renamed, used = {}, [], set()
    for node in nodes:
        page = node.get("name")
        target = gltf_to_blender(node.get("translation", [0.0, 0.0, 0.0]))
        at_place = [o for o in objects if o.name not in used and all(abs(a - b) <= 1e-5 for a, b in zip(o.matrix_world.translation, target))]
        named = [o for o in at_place if o.name == page]
        if len(named) == 1:
            obj = named[0]
        elif len(at_place) == 1:
            obj = at_place[0]
            renamed.append({"page": page, "object": obj.name})
        else:
            check.fail(page, f"no single Blender object at the node's place {target} ({len(at_place)} found)")
            continue
        if page in matched:
            check.fail(page, "two glTF nodes of the same name")
            continue
        matched[page] = (obj, node)
        used.add(obj.name)
    for obj in objects:
        if obj.name not in used:
            check.fail(obj.name, "a Blender object no glTF node accounts for")
    return matched, renamed


def gltf_material(gltf, node):
    """The glTF material of the node's (one-primitive) mesh, {} when there is none."""
    meshes, materials = gltf.get("meshes", []), gltf.get("materials", [])
    primitives = meshes[node["mesh"]].get("primitives", []) if node["mesh"] < len(meshes) else []
    index = primitives[0].get("material") if primitives else None
    return materials[index] if index is not None and index < len(materials) else {}


def principled(material):
    nodes = [n for n in material.node_tree.nodes if n.bl_idname == "ShaderNodeBsdfPrincipled"]
    return nodes[0] if len(nodes) == 1 else None


def output_volume(material):
    """The node on the material output's Volume socket, or None."""
    for node in material.node_tree.nodes:
        if node.bl_idname == "ShaderNodeOutputMaterial" and node.is_active_output:
            links = node.inputs["Volume"].links
            return links[0].from_node if links else None
    return None


def settings_thickness(material):
    """Thickness of the importer's 'glTF Material Output' group (kept for re-export)."""
    for node in material.node_tree.nodes:
        if node.bl_idname == "ShaderNodeGroup" and node.node_tree is not None and node.node_tree.name.startswith("glTF Material Output"):
            if "Thickness" in node.inputs:
                return value(node.inputs["Thickness"])
    return None


def main(directory):
    gltf_path, gltf, rows = load(directory)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.app.debug_value = 1  # the importer then logs warnings and errors only
    check = Checker()
    not_imported, approximated = {}, []

    units = bpy.context.scene.unit_settings
    # glTF's unit is the metre and the importer converts nothing: densities below are per
    # Blender unit, a metre at scale 1.
    if units.scale_length != 1.0:
        check.fail("scene", f"unit scale {units.scale_length}, expected 1 (metres)")
    result = bpy.ops.import_scene.gltf(filepath=gltf_path)
    if result != {"FINISHED"}:
        check.fail("import", f"import_scene.gltf returned {sorted(result)}")

    matched, renamed = match_objects(gltf, check)
    counts = {a: 0 for a in APPEARANCES}
    for page in rows:
        if page not in matched:
            check.fail(page, "a row of engine_params.csv with no imported object")
    for page in matched:
        if page not in rows:
            check.fail(page, "an imported object with no row in engine_params.csv")

    for page, (obj, node) in sorted(matched.items()):
        row = rows.get(page)
        if row is None:
            continue
        appearance = row["appearance"]
        if appearance not in counts:
            check.fail(page, f"appearance {appearance!r} is none of {APPEARANCES}")
            continue
        slots = [m for m in obj.data.materials if m is not None]
        if len(slots) != 1:
            check.fail(page, f"{len(slots)} materials on the object, expected 1")
            continue
        material = slots[0]
        # Material name = display name; Blender adds .001, .002, … to repeated names
        # (Mercury is both a metal and a liquid page).
        base_name, _, suffix = material.name.rpartition(".")
        if material.name != row["display_name"] and not (base_name == row["display_name"] and suffix.isdigit()):
            check.fail(page, f"material {material.name!r}, expected {row['display_name']!r}")
        bsdf = principled(material)
        if bsdf is None:
            check.fail(page, "no single Principled BSDF in the material")
            continue
        if not bsdf.outputs[0].is_linked:
            check.fail(page, "the Principled BSDF reaches no output")

        sockets = {
            "Base Color": socket(bsdf, "Base Color"),
            "Metallic": socket(bsdf, "Metallic"),
            "Roughness": socket(bsdf, "Roughness"),
            "IOR": socket(bsdf, "IOR"),
            "Transmission": socket(bsdf, "Transmission Weight"),
            "Specular Tint": socket(bsdf, "Specular Tint"),
            "Specular IOR Level": socket(bsdf, "Specular IOR Level"),
        }
        read = {}
        for name, sock in sockets.items():
            if sock is None:
                read[name] = None
            elif sock.is_linked:
                # A factor-only glTF material makes the importer set the socket's value
                # (pbrMetallicRoughness.py: base_color / metallic_roughness / transmission
                # / specular write default_value when there is no texture): a link means
                # something else drives it.
                check.fail(page, f"{name} is driven by a node, expected a constant")
                read[name] = None
            else:
                read[name] = value(sock)

        n_d = number(row["n_d"])
        roughness = number(row["export_roughness"])
        volume = output_volume(material)

        # Roughness: pbrMetallicRoughness.roughnessFactor -> 'Roughness' (metallic_roughness()).
        check.scalar(page, "Roughness", read["Roughness"], roughness)
        # KHR_materials_specular: specularFactor (default 1) -> 'Specular IOR Level' = 0.5 ×
        # specularFactor (specular()); no material sets specularFactor.
        check.scalar(page, "Specular IOR Level", read["Specular IOR Level"], 0.5)

        if appearance == "metal":
            # baseColorFactor -> 'Base Color' (base_color(), factor only); the exporter
            # clamps F0 to [0, 1].
            check.colour(page, "Base Color", read["Base Color"], clamp01(rgb(row, "f0_linear")))
            check.scalar(page, "Metallic", read["Metallic"], 1.0)
            # No KHR_materials_ior: the importer writes its default, GLTF_IOR.
            check.scalar(page, "IOR", read["IOR"], GLTF_DEFAULT_IOR)
            check.scalar(page, "Transmission", read["Transmission"], 0.0)
            check.colour(page, "Specular Tint", read["Specular Tint"], [1.0, 1.0, 1.0])
            if volume is not None:
                check.fail(page, f"a volume ({volume.bl_idname}) on an opaque metal")
        elif appearance in ("transparent", "tinted"):
            check.colour(page, "Base Color", read["Base Color"], [1.0, 1.0, 1.0])
            check.scalar(page, "Metallic", read["Metallic"], 0.0)
            # KHR_materials_ior.ior -> 'IOR' (pbr_metallic_roughness(), end); the exporter
            # writes n_d, at least 1.
            if n_d is None:
                check.fail(page, "no n_d in the table for a transparent page")
            else:
                check.scalar(page, "IOR", read["IOR"], max(n_d, 1.0))
            # KHR_materials_transmission.transmissionFactor -> 'Transmission Weight'
            # (transmission()), which also turns on the material's screen-space refraction.
            check.scalar(page, "Transmission", read["Transmission"], 1.0)
            if not material.use_raytrace_refraction:
                check.fail(page, "screen-space refraction off on a transmissive material")
            check.colour(page, "Specular Tint", read["Specular Tint"], [1.0, 1.0, 1.0])
            # KHR_materials_volume with thicknessFactor != 0 -> a Volume Absorption node on
            # the output's Volume socket (volume()): Color = attenuationColor (default
            # white), Density = 1 / attenuationDistance (default +inf, so 0), in the
            # scene's unit: glTF distances are metres, which the importer keeps.
            if volume is None or volume.bl_idname != "ShaderNodeVolumeAbsorption":
                check.fail(page, f"volume: {volume.bl_idname if volume else 'none'}, expected a Volume Absorption")
            else:
                for name in ("Color", "Density"):
                    if volume.inputs[name].is_linked:
                        check.fail(page, f"Volume Absorption {name} is driven by a node, expected a constant")
                colour = value(volume.inputs["Color"])
                density = value(volume.inputs["Density"])
                if appearance == "tinted":
                    attenuation = rgb(row, "attenuation_colour")
                    distance = number(row["attenuation_distance_m"])
                    if attenuation is None or distance is None or distance <= 0:
                        check.fail(page, "tinted page without attenuation colour and distance in the table")
                    else:
                        # The exporter clamps the colour to [0, 1].
                        check.colour(page, "Volume Absorption Color", colour, clamp01(attenuation))
                        check.scalar(page, "Volume Absorption Density", density, 1.0 / distance)
                        # Blender absorbs σ = (1 − Color)·Density per metre (Cycles and
                        # EEVEE's Volume Absorption); KHR_materials_volume means
                        # σ = −ln(attenuationColor) / attenuationDistance. Light through the
                        # sphere's diameter, by the glTF and in Blender:
                        diameter = 2.0 * max(obj.matrix_world.to_scale()) * max(v.co.length for v in obj.data.vertices)
                        gltf_t = [c ** (diameter / distance) if c > 0 else 0.0 for c in clamp01(attenuation)]
                        blender_t = [math.exp(-(1.0 - c) * density * diameter) for c in colour[:3]]
                        approximated.append({
                            "page": page,
                            "path_m": round(diameter, 6),
                            "gltf_transmittance": [round(t, 5) for t in gltf_t],
                            "blender_transmittance": [round(t, 5) for t in blender_t],
                        })
                else:
                    check.colour(page, "Volume Absorption Color", colour, [1.0, 1.0, 1.0])
                    check.scalar(page, "Volume Absorption Density", density, 0.0)
            # thicknessFactor -> Thickness of the 'glTF Material Output' group (volume());
            # Blender does not render with it (it traces the mesh's own volume) but keeps it
            # for export. The exporter writes the sphere's diameter in mesh units.
            diameter_mesh = 2.0 * max(v.co.length for v in obj.data.vertices)
            check.scalar(page, "glTF Material Output Thickness", settings_thickness(material), diameter_mesh)
        else:  # opaque
            check.colour(page, "Base Color", read["Base Color"], [0.0, 0.0, 0.0])
            check.scalar(page, "Metallic", read["Metallic"], 0.0)
            ior = max(n_d, 1.0) if n_d is not None else GLTF_DEFAULT_IOR
            check.scalar(page, "IOR", read["IOR"], ior)
            check.scalar(page, "Transmission", read["Transmission"], 0.0)
            # KHR_materials_specular.specularColorFactor -> 'Specular Tint' (specular(),
            # color_factor_and_texture(): the factor as is, above 1 too). The exporter
            # writes F0 over the F0 the ior gives, so that the two make the page's F0.
            f0 = rgb(row, "f0_linear")
            from_ior = f0_of_ior(ior)
            if f0 is None or from_ior <= 0:
                check.fail(page, "no F0 in the table, or an ior of 1, for an opaque page")
            else:
                check.colour(page, "Specular Tint", read["Specular Tint"], [max(v, 0.0) / from_ior for v in f0])
            if volume is not None:
                check.fail(page, f"a volume ({volume.bl_idname}) on an opaque dielectric")

        # What the glTF material carries that Blender has no place for. Dispersion:
        # io_scene_gltf2 does not list KHR_materials_dispersion among the extensions it
        # handles, and Blender's Principled BSDF has no Dispersion input (5.0); should a
        # later Blender keep it, the input shows up here and the entry goes away.
        extensions = gltf_material(gltf, node).get("extensions", {})
        dispersion = extensions.get("KHR_materials_dispersion", {}).get("dispersion")
        if dispersion is not None:
            kept = [n for n in material.node_tree.nodes if "Dispersion" in n.inputs and value(n.inputs["Dispersion"]) != 0.0]
            if not kept:
                not_imported.setdefault("KHR_materials_dispersion.dispersion", []).append(page)
        counts[appearance] += 1

    summary = {
        "blender": bpy.app.version_string,
        "materials": len(bpy.data.materials),
        "checked": counts,
        "failures": check.failures,
        "renamed": renamed,
        "not_imported": [{"property": k, "pages": len(v), "examples": v[:3]} for k, v in sorted(not_imported.items())],
        "approximated": approximated,
    }
    print(json.dumps(summary))
    return 0 if not check.failures else 1


if __name__ == "__main__":
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        sys.exit(2)
    sys.exit(main(sys.argv[1]))
