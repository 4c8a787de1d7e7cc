"""The Blender paste-in block's volume, rendered in Blender (bpy, Cycles on the CPU): for every
tinted page, a 5 cm slab with a Volume Absorption of exactly the numbers the block gives,
seen against a white world, must pass the colour the glTF path gives the same thickness.

Usage: python check_blender_paste.py DIR OUT_DIR
DIR holds engine_params.csv and params/*.json of the same `nklut params` run; OUT_DIR gets
the renders (EXR) and blender_paste.json.

Per tinted page (engine_params.csv appearance = tinted), the Blender block of its paste-in
JSON is parsed for the numbers a user types: "Color #rrggbb (linear (r, g, b)), Density X"
(the linear triplet and the density as printed, 6 significant digits). The glTF path's
transmittance of a piece of thickness d = 0.05 m is T_c = c_c^(d/D), c = the table's
attenuation_colour_* clamped to [1e-6, 1] (what every export writes) and D its
attenuation_distance_m (KHR_materials_volume: σ_c = −ln(c_c)/D, T = e^(−σ d)).

Rig: scene units metres (unit scale 1); a cube scaled to a slab 0.5 m x 0.05 m x 0.5 m (the
0.05 m along the view), its material a Volume Absorption node into the Material Output's
Volume and no Surface shader (Cycles then treats the mesh as the medium's boundary only: no
reflection, no refraction); an orthographic camera of scale 1 m looking through the slab at
normal incidence, 32 x 32 pixels, so the centre 16 x 16 see the slab and the corners the
world; the world a uniform white background of strength 1 (the only light); Cycles, 1
sample, a 0.01-pixel box filter, no denoising, volume bounces 0, 32-bit float EXR of the
scene-linear render (no view transform applies to the EXR). Asserted:

- the block of every tinted page gives a Color triplet in [0, 1] and a Density > 0, and
  its stated "a 0.05 m piece then passes linear (…)" is T within 5e-5 (its 4 decimals);
- every world pixel (the 4 x 4 of each corner) is (1, 1, 1) within TOLERANCE: the rig's
  background is what T is measured against;
- every slab pixel (the centre 12 x 12, clear of the slab's edges) is T_c per channel within
  TOLERANCE = 1e-5 absolute;
- the importer-style mapping (Color = c, Density = 1/D, what Blender's glTF importer
  builds) rendered the same way misses T by more than TOLERANCE in some channel of
  3d/glass/soda-lime-green (printed for every tinted page): the check sees a wrong mapping.

The tolerance: Cycles integrates a homogeneous absorbing medium with no scattering in closed
form, so the render is deterministic (measured: 64 samples, another seed and a 1.5-pixel
filter change no slab pixel by more than 7.2e-7). What is left is the block's printing and
float32. The block gives Density and Color to 6 significant digits: Density's relative error
≤ 5e-6 moves T = e^(−x) (x = σd) by ≤ x e^(−x) · 5e-6 ≤ 1.9e-6 (x e^(−x) ≤ 1/e); Color's
absolute error ≤ 5e-7 moves it by ≤ Density · d · 5e-7 · e^(−x), ≤ 3.4e-6 on the 3d shelf
(Density · d ≤ 6.7); float32 (Blender's sockets and film) adds about 1e-6. So ≤ 6.3e-6 on
the 3d shelf; TOLERANCE = 1e-5 holds that and still sees a block printed to 4 significant
digits (Density and Color so rounded miss T by 1.1e-5 to 4.4e-5 on three of the five pages).
Measured with bpy 5.0.1: at most 2.2e-6 (soda-lime-clear R); the importer-style mapping
misses by 2.1e-3 to 0.11.

Prints a table and writes OUT_DIR/blender_paste.json; exits 1 on any failure, 2 when DIR
lacks a file.
"""

import csv
import glob
import json
import math
import os
import re
import sys

import bpy

TOLERANCE = 1e-5
THICKNESS_M = 0.05
MIN_TRANSMITTANCE = 1e-6
SIZE = 32
# The centre 12 x 12 pixels (of the slab's 16 x 16) and the 4 x 4 of each corner.
SLAB_PIXELS = [(x, y) for x in range(10, 22) for y in range(10, 22)]
WORLD_PIXELS = [(x0 + x, y0 + y) for x0 in (0, SIZE - 4) for y0 in (0, SIZE - 4) for x in range(4) for y in range(4)]
WRONG_MAPPING_PAGE = "3d/glass/soda-lime-green"
VOLUME = re.compile(r"Volume Absorption node.*?Color (#[0-9a-fA-F]{6}) \(linear \(([^)]*)\)\), Density ([^ ]+) .*?a ([0-9.]+) m piece then passes linear \(([^)]*)\)")


def numbers(text):
    return [float(v) for v in text.split(",")]


def block_volume(block):
    """(colour, density, stated thickness, stated transmittance) as the block prints them; None when absent."""
    m = VOLUME.search(block)
    if not m:
        return None
    return numbers(m.group(2)), float(m.group(3)), float(m.group(4)), numbers(m.group(5))


def scene_setup():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.unit_settings.system = "METRIC"
    scene.unit_settings.scale_length = 1.0
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = 1
    scene.cycles.use_denoising = False
    scene.cycles.use_adaptive_sampling = False
    scene.cycles.pixel_filter_type = "BOX"
    scene.cycles.filter_width = 0.01
    scene.cycles.seed = 0
    scene.cycles.volume_bounces = 0
    scene.render.resolution_x = SIZE
    scene.render.resolution_y = SIZE
    scene.render.resolution_percentage = 100
    scene.render.film_transparent = False
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    scene.render.image_settings.color_mode = "RGBA"
    scene.view_settings.view_transform = "Standard"
    world = bpy.data.worlds.new("white")
    if world.node_tree is None:  # Blender 4 (Blender 5 gives every world and material nodes)
        world.use_nodes = True
    background = world.node_tree.nodes["Background"]
    background.inputs["Color"].default_value = (1, 1, 1, 1)
    background.inputs["Strength"].default_value = 1.0
    scene.world = world
    # The default cube is 2 m on a side: scaled to 0.5 x 0.05 x 0.5 m, the 0.05 m along y.
    bpy.ops.mesh.primitive_cube_add(size=2.0, location=(0, 0, 0))
    slab = bpy.context.object
    slab.scale = (0.25, THICKNESS_M / 2, 0.25)
    bpy.ops.object.transform_apply(location=False, rotation=False, scale=True)
    camera_data = bpy.data.cameras.new("camera")
    camera_data.type = "ORTHO"
    camera_data.ortho_scale = 1.0
    camera = bpy.data.objects.new("camera", camera_data)
    camera.location = (0, -2, 0)
    camera.rotation_euler = (math.radians(90), 0, 0)
    scene.collection.objects.link(camera)
    scene.camera = camera
    return scene, slab


def absorption_material(name, colour, density):
    """A material with a Volume Absorption (colour, density) on the output's Volume and no surface."""
    material = bpy.data.materials.new(name)
    if material.node_tree is None:
        material.use_nodes = True
    nodes = material.node_tree.nodes
    nodes.clear()
    output = nodes.new("ShaderNodeOutputMaterial")
    volume = nodes.new("ShaderNodeVolumeAbsorption")
    volume.inputs["Color"].default_value = (*colour, 1.0)
    volume.inputs["Density"].default_value = density
    material.node_tree.links.new(volume.outputs["Volume"], output.inputs["Volume"])
    return material


def render(scene, slab, material, path):
    slab.data.materials.clear()
    slab.data.materials.append(material)
    scene.render.filepath = path
    bpy.ops.render.render(write_still=True)
    image = bpy.data.images.load(path)
    pixels = list(image.pixels)
    bpy.data.images.remove(image)
    return lambda x, y, c: pixels[4 * (y * SIZE + x) + c]


def deviation(pixel, where, expected):
    """The largest |pixel - expected_c| over the pixels `where`, per channel."""
    return [max(abs(pixel(x, y, c) - expected[c]) for x, y in where) for c in range(3)]


def main():
    args = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else sys.argv[1:]
    if len(args) != 2:
        sys.exit("usage: check_blender_paste.py DIR OUT_DIR")
    directory, out = (os.path.abspath(p) for p in args)
    csv_path = os.path.join(directory, "engine_params.csv")
    if not os.path.isfile(csv_path):
        print(f"check_blender_paste: {csv_path} missing", file=sys.stderr)
        sys.exit(2)
    os.makedirs(out, exist_ok=True)
    with open(csv_path, newline="", encoding="utf-8") as f:
        tinted = [row for row in csv.DictReader(f) if row["appearance"] == "tinted"]
    blocks = {}
    for path in sorted(glob.glob(os.path.join(directory, "params", "*.json"))):
        paste = json.load(open(path, encoding="utf-8"))
        blocks[paste["page"]] = (os.path.basename(path), paste["engines"]["blender"])
    scene, slab = scene_setup()
    failures, results = [], []
    if not tinted:
        failures.append("no tinted page in engine_params.csv")
    print(f"Blender {bpy.app.version_string}, Cycles CPU; {SIZE} x {SIZE}, 1 sample; slab {THICKNESS_M} m; tolerance {TOLERANCE}")
    print(f"{'page':<26} c {'Color':>9} {'Density':>9} {'glTF T':>9} {'render':>9} {'|dev|':>9} {'importer':>9} {'|dev|':>9}")
    for row in tinted:
        page = row["page"]
        if page not in blocks:
            failures.append(f"{page}: no paste-in JSON")
            continue
        file, block = blocks[page]
        parsed = block_volume(block)
        if parsed is None:
            failures.append(f"{page}: {file}'s Blender block has no Volume Absorption Color and Density")
            continue
        colour, density, stated_d, stated_t = parsed
        if len(colour) != 3 or any(not 0 <= v <= 1 for v in colour) or not density > 0:
            failures.append(f"{page}: Color {colour}, Density {density}")
            continue
        c = [min(max(float(row[f"attenuation_colour_{ch}"]), MIN_TRANSMITTANCE), 1.0) for ch in "rgb"]
        distance = float(row["attenuation_distance_m"])
        expected = [v ** (THICKNESS_M / distance) for v in c]
        if stated_d != THICKNESS_M or any(abs(stated_t[i] - expected[i]) > 5e-5 for i in range(3)):
            failures.append(f"{page}: the block states {stated_t} through {stated_d} m, the glTF path {expected}")
        stem = page.replace("/", "__")
        pixel = render(scene, slab, absorption_material(f"block {stem}", colour, density), os.path.join(out, f"{stem}.exr"))
        world_dev = deviation(pixel, WORLD_PIXELS, [1.0, 1.0, 1.0])
        slab_dev = deviation(pixel, SLAB_PIXELS, expected)
        wrong = render(scene, slab, absorption_material(f"importer {stem}", c, 1.0 / distance), os.path.join(out, f"{stem}-importer.exr"))
        wrong_dev = deviation(wrong, SLAB_PIXELS, expected)
        for i in range(3):
            print(
                f"{page:<26} {'RGB'[i]} {colour[i]:9.6f} {density:9.4f} {expected[i]:9.6f} {pixel(16, 16, i):9.6f} {slab_dev[i]:9.2e} {wrong(16, 16, i):9.6f} {wrong_dev[i]:9.2e}"
            )
        if max(world_dev) > TOLERANCE:
            failures.append(f"{page}: world pixels off white by {max(world_dev):.3e}")
        if max(slab_dev) > TOLERANCE:
            failures.append(f"{page}: the slab passes {[pixel(16, 16, i) for i in range(3)]}, the glTF path {expected} (deviation {max(slab_dev):.3e} > {TOLERANCE})")
        if page == WRONG_MAPPING_PAGE and max(wrong_dev) <= TOLERANCE:
            failures.append(f"{page}: the importer-style mapping stays within {TOLERANCE} ({max(wrong_dev):.3e}): the check cannot see a wrong mapping")
        results.append(
            {
                "page": page,
                "file": file,
                "colour": colour,
                "density": density,
                "gltf_transmittance": expected,
                "rendered": [pixel(16, 16, i) for i in range(3)],
                "max_deviation": slab_dev,
                "world_max_deviation": world_dev,
                "importer_rendered": [wrong(16, 16, i) for i in range(3)],
                "importer_max_deviation": wrong_dev,
            }
        )
    if WRONG_MAPPING_PAGE not in [r["page"] for r in results]:
        failures.append(f"{WRONG_MAPPING_PAGE} not checked: the wrong-mapping assertion did not run")
    json.dump(
        {"blender": bpy.app.version_string, "tolerance": TOLERANCE, "thickness_m": THICKNESS_M, "results": results, "failures": failures},
        open(os.path.join(out, "blender_paste.json"), "w"),
        indent=1,
    )
    if failures:
        print("FAILED:\n" + "\n".join(failures))
        sys.exit(1)
    print(f"check_blender_paste: {len(results)} tinted pages, every slab pixel within {TOLERANCE} of the glTF path")


main()
