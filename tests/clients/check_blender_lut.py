"""clients/blender/nklut_lut.py in Blender (bpy, Cycles on the CPU): renders a sphere per page
and encoding with the node group's Fresnel term as emission, and again with its cos theta,
then compares every sphere pixel against the exact Fresnel curve of the row's three-channel
(n, k) at that pixel's cos theta.

Usage: python check_blender_lut.py LUTS_DIR OUT_DIR [--pages ID,...] [--encodings E,...]

Rig: a UV sphere of radius 1 (128 x 64, smooth), a 45 degree camera at distance 3, 128 x 128
pixels, Cycles with 1 sample, a 0.01-pixel box filter and the same seed for both renders
(so both see the same point per pixel), transparent film over a black world, 32-bit float
EXR output. Sphere pixels: alpha = 1. Asserted, per encoding, page and channel:

- |F - F_exact(cos)| <= the manifest's error_vs_exact.max_absolute + TOLERANCE, on at least
  3000 sphere pixels reaching cos theta < 0.01 (Cycles' smooth normals at pixel centres stop
  at cos theta = 0.0039 on this sphere: the silhouette's cos theta = 0 itself is covered by
  tests/three_lut.rs, not here);
- the same with v = (row + 0.5)/rows (the row counted from the bottom, as Blender's image
  origin is) exceeds that bound by more than 0.1 for every page: the check sees a wrong row.

Prints a table and writes OUT_DIR/blender_lut.json; exits 1 on any failure.
"""

import json
import math
import os
import sys

import bpy

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "clients", "blender"))
import nklut_lut  # noqa: E402

SIZE = 128
TOLERANCE = 1e-4
PAGES = ["3d/metals/copper", "3d/metals/gold", "3d/glass/soda-lime-green", "3d/liquids/water"]
ENCODINGS = ["f16", "f32", "unorm16", "unorm8", "unorm8-srgb"]


def exact_fresnel(n, k, c):
    """Unpolarised reflectance of n + ik from vacuum at cos theta (Born & Wolf 1.5, 14.2)."""
    eps = complex(n * n - k * k, 2 * n * k)
    w = (eps - (1 - c * c)) ** 0.5
    if c == 0 and w == 0:
        return 1.0
    rs = abs((c - w) / (c + w)) ** 2
    rp = abs((eps * c - w) / (eps * c + w)) ** 2
    return 0.5 * (rs + rp)


def scene_setup():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = 1
    scene.cycles.use_denoising = False
    scene.cycles.pixel_filter_type = "BOX"
    scene.cycles.filter_width = 0.01
    scene.cycles.seed = 0
    scene.render.resolution_x = SIZE
    scene.render.resolution_y = SIZE
    scene.render.resolution_percentage = 100
    scene.render.film_transparent = True
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    scene.render.image_settings.color_mode = "RGBA"
    scene.view_settings.view_transform = "Standard"
    world = bpy.data.worlds.new("black")
    world.color = (0, 0, 0)
    scene.world = world
    bpy.ops.mesh.primitive_uv_sphere_add(segments=128, ring_count=64, radius=1.0)
    sphere = bpy.context.object
    bpy.ops.object.shade_smooth()
    camera_data = bpy.data.cameras.new("camera")
    camera_data.angle = math.radians(45)
    camera = bpy.data.objects.new("camera", camera_data)
    camera.location = (0, -3, 0)
    camera.rotation_euler = (math.radians(90), 0, 0)
    scene.collection.objects.link(camera)
    scene.camera = camera
    return scene, sphere


def render(scene, sphere, material, path):
    sphere.data.materials.clear()
    sphere.data.materials.append(material)
    scene.render.filepath = path
    bpy.ops.render.render(write_still=True)
    image = bpy.data.images.load(path)
    pixels = list(image.pixels)
    bpy.data.images.remove(image)
    return pixels


def compare(row, f_pixels, cos_pixels):
    index = row["index_three_channel"]
    stats = {"pixels": 0, "grazing_pixels": 0, "min_cos": 1.0, "max": [0.0, 0.0, 0.0], "max_at_cos": [None] * 3}
    for p in range(SIZE * SIZE):
        if f_pixels[4 * p + 3] < 0.5:
            continue
        cos = cos_pixels[4 * p]
        stats["pixels"] += 1
        stats["grazing_pixels"] += cos == 0.0
        stats["min_cos"] = min(stats["min_cos"], cos)
        for c in range(3):
            diff = abs(f_pixels[4 * p + c] - exact_fresnel(index[c]["n"], index[c]["k"], cos))
            if diff > stats["max"][c]:
                stats["max"][c], stats["max_at_cos"][c] = diff, cos
    return stats


def main():
    args = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else sys.argv[1:]
    positional, pages, encodings = [], PAGES, ENCODINGS
    i = 0
    while i < len(args):
        if args[i] == "--pages":
            pages, i = args[i + 1].split(","), i + 2
        elif args[i] == "--encodings":
            encodings, i = args[i + 1].split(","), i + 2
        else:
            positional.append(args[i])
            i += 1
    if len(positional) != 2:
        sys.exit("usage: check_blender_lut.py LUTS_DIR OUT_DIR [--pages ID,...] [--encodings E,...]")
    luts, out = (os.path.abspath(p) for p in positional)
    os.makedirs(out, exist_ok=True)
    manifest = json.load(open(os.path.join(luts, "manifest.json")))
    scene, sphere = scene_setup()
    results, failures = [], []
    print(f"Blender {bpy.app.version_string}, Cycles CPU; {SIZE} x {SIZE}, 1 sample")
    print(f"{'encoding':<12} {'page':<26} c {'max':>9} {'manifest':>9} pixels min_cos max_at_cos")
    for encoding in encodings:
        t = nklut_lut.texture_set(manifest, "three-channel", encoding)
        image = nklut_lut.load_atlas(os.path.join(luts, t["atlas"]["file"]), encoding)
        rows = t["atlas"]["height"]
        for page in pages:
            row = next(r for r in t["rows"] if r["page"] == page)
            stem = f"{encoding}-{page.replace('/', '__')}"
            f_mat = nklut_lut.fresnel_debug_material(f"F {stem}", image, row["row"], rows, "Fresnel")
            cos_mat = nklut_lut.fresnel_debug_material(f"cos {stem}", image, row["row"], rows, "Cos")
            f_pixels = render(scene, sphere, f_mat, os.path.join(out, f"{stem}-F.exr"))
            cos_pixels = render(scene, sphere, cos_mat, os.path.join(out, f"{stem}-cos.exr"))
            stats = compare(row, f_pixels, cos_pixels)
            promised = row["error_vs_exact"]["max_absolute"]
            for c in range(3):
                print(f"{encoding:<12} {page:<26} {'RGB'[c]} {stats['max'][c]:9.3e} {promised[c]:9.3e} {stats['pixels']:6} {stats['min_cos']:.4f} {stats['max_at_cos'][c]:.4f}")
                if stats["max"][c] > promised[c] + TOLERANCE:
                    failures.append(f"{encoding} {page} channel {c}: {stats['max'][c]:.3e} > {promised[c]:.3e} + {TOLERANCE}")
            if stats["pixels"] < 3000 or stats["min_cos"] > 0.01:
                failures.append(f"{encoding} {page}: {stats['pixels']} sphere pixels, smallest cos theta {stats['min_cos']}")
            results.append({"encoding": encoding, "page": page, "manifest_max": promised, **stats})
            if encoding == encodings[0]:
                # The row counted from the bottom: another material's row.
                wrong = nklut_lut.fresnel_debug_material(f"wrong {stem}", image, rows - 1 - row["row"], rows, "Fresnel")
                wrong_stats = compare(row, render(scene, sphere, wrong, os.path.join(out, f"{stem}-wrong.exr")), cos_pixels)
                over = max(wrong_stats["max"][c] - promised[c] for c in range(3))
                print(f"{encoding:<12} {page:<26} wrong row order: exceeds the bound by {over:.3e}")
                if over < 0.1:
                    failures.append(f"{page}: the wrong row order exceeds the bound by only {over:.3e}")
                results[-1]["wrong_row_excess"] = over
    json.dump({"blender": bpy.app.version_string, "results": results, "failures": failures}, open(os.path.join(out, "blender_lut.json"), "w"), indent=1)
    if failures:
        print("FAILED:\n" + "\n".join(failures))
        sys.exit(1)
    print("check_blender_lut: every pixel within the manifest's maximum")


main()
