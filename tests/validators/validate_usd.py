"""Validate a USD layer with USD's own validators (PyPI `usd-core`): every validator of
the UsdValidation registry (the framework `usdchecker` runs: stage metadata, shader
compliance with the shader registry, material encapsulation, …) over the opened stage —
and its MaterialX shaders with MaterialX (PyPI `materialx`).

usd-core ships without USD's MaterialX plugin (UsdMtlx), so its shader registry knows no
MaterialX node and reports `MissingShaderIdInRegistry` for a shader whose `info:id` is a
MaterialX node definition (`ND_open_pbr_surface_surfaceshader`). Those reports are set
aside only where MaterialX's standard libraries define that node; each such shader is then
checked by MaterialX itself: a document with that node and the shader's authored inputs
(USD color3f → color3, float → float) passes Document.validate(), MaterialX's GLSL
generator compiles it, and every authored colour input reaches the generated pixel shader
as a uniform with the authored value (to 6 decimals) — for tinted glass, its
transmission_color. Every other error stands.

Usage: python validate_usd.py FILE.usda
Prints one JSON line: {"valid": bool, "errors": [...], "materials": N, "shaders": N,
"previewSurfaces": N, "mtlxShaders": N, "mtlxSurfaceOutputs": N, "tintInGlsl": [prim paths
whose transmission_color reached the GLSL], "version": "0.26.x"}. Exit status 0 when
valid, 1 when not, 2 when the file does not open.
"""
import json
import re
import sys

from pxr import Sdf, Usd, UsdShade, UsdValidation

import MaterialX as mx
import MaterialX.PyMaterialXGenGlsl as mx_gen_glsl
import MaterialX.PyMaterialXGenShader as mx_gen_shader

MISSING_ID = "MissingShaderIdInRegistry"


def check_mtlx_shader(shader, stdlib, errors):
    """MaterialX's own checks of one USD shader whose id names a MaterialX nodedef.

    Returns whether its transmission_color reached the generated GLSL."""
    path = str(shader.GetPath())
    nodedef = stdlib.getNodeDef(shader.GetIdAttr().Get())
    if nodedef is None:
        errors.append(f"{path}: no MaterialX node definition {shader.GetIdAttr().Get()}")
        return False
    doc = mx.createDocument()
    doc.setDataLibrary(stdlib)
    node = doc.addNodeInstance(nodedef, "shader")
    colours = {}
    for usd_input in shader.GetInputs():
        name, value = usd_input.GetBaseName(), usd_input.Get()
        kind = usd_input.GetTypeName()
        if kind == Sdf.ValueTypeNames.Color3f:
            node.setInputValue(name, mx.Color3(*[float(v) for v in value]), "color3")
            colours[name] = [float(v) for v in value]
        elif kind == Sdf.ValueTypeNames.Float:
            node.setInputValue(name, float(value), "float")
        else:
            errors.append(f"{path}: input {name} of type {kind} has no MaterialX counterpart here")
    material = doc.addMaterialNode("material", node)
    valid, message = doc.validate()
    if not valid:
        errors.append(f"{path}: MaterialX validate: {message[:200]}")
        return False
    generator = mx_gen_glsl.GlslShaderGenerator.create()
    context = mx_gen_shader.GenContext(generator)
    context.registerSourceCodeSearchPath(mx.getDefaultDataSearchPath())
    try:
        code = generator.generate("shader", node, context)
        pixel = code.getSourceCode(mx_gen_shader.PIXEL_STAGE)
    except Exception as error:  # a generator error names the shader
        errors.append(f"{path}: GLSL generation: {str(error)[:200]}")
        return False
    # Public inputs become uniforms with their values: `uniform vec3 <name> = vec3(r, g, b);`.
    uniforms = {}
    for match in re.finditer(r"uniform\s+vec3\s+(\w+)\s*=\s*vec3\(([^)]*)\)", pixel):
        uniforms[match.group(1)] = [float(v) for v in match.group(2).split(",")]
    for name, value in colours.items():
        found = [u for u in uniforms if u == name or u.endswith("_" + name)]
        if not found or not any(all(abs(a - b) <= 1e-6 for a, b in zip(uniforms[u], value)) for u in found):
            errors.append(f"{path}: {name} {value} does not reach the GLSL (uniforms {sorted(found)})")
    return "transmission_color" in colours and not any(e.startswith(path) for e in errors)


def main(path):
    stage = Usd.Stage.Open(path)
    if stage is None:
        print(json.dumps({"valid": False, "errors": ["the layer does not open"], "materials": 0}))
        return 2
    stdlib = mx.createDocument()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), stdlib)
    registry = UsdValidation.ValidationRegistry()
    validators = registry.GetOrLoadAllValidators()
    context = UsdValidation.ValidationContext(validators)
    found = context.Validate(stage)
    shaders = [UsdShade.Shader(p) for p in stage.Traverse() if p.IsA(UsdShade.Shader)]
    mtlx_ids = {str(s.GetPath()): s.GetIdAttr().Get() for s in shaders if stdlib.getNodeDef(s.GetIdAttr().Get() or "") is not None}
    errors = []
    for e in found:
        if e.GetType() != UsdValidation.ValidationErrorType.Error:
            continue
        message = e.GetMessage()
        if e.GetName() == MISSING_ID and any(f"<{p}>" in message and f"'{i}'" in message for p, i in mtlx_ids.items()):
            continue  # a MaterialX node: checked by MaterialX below
        errors.append(f"{e.GetName()}: {message}")
    materials = [p for p in stage.Traverse() if p.IsA(UsdShade.Material)]
    preview = [s for s in shaders if s.GetIdAttr().Get() == "UsdPreviewSurface"]
    tinted = [str(s.GetPath()) for s in shaders if str(s.GetPath()) in mtlx_ids and check_mtlx_shader(s, stdlib, errors)]
    mtlx_outputs = 0
    # Every material's surface output reaches a shader; a mtlx surface output a MaterialX one.
    for material in materials:
        source = UsdShade.Material(material).ComputeSurfaceSource()
        if not source or not source[0]:
            errors.append(f"{material.GetPath()}: no surface shader")
        mtlx = UsdShade.Material(material).ComputeSurfaceSource("mtlx")
        if mtlx and mtlx[0] and str(mtlx[0].GetPath()) in mtlx_ids:
            mtlx_outputs += 1
    version = ".".join(str(v) for v in Usd.GetVersion())
    print(
        json.dumps(
            {
                "valid": not errors,
                "errors": errors[:20],
                "materials": len(materials),
                "shaders": len(shaders),
                "previewSurfaces": len(preview),
                "mtlxShaders": len(mtlx_ids),
                "mtlxSurfaceOutputs": mtlx_outputs,
                "tintInGlsl": tinted,
                "version": version,
            }
        )
    )
    return 0 if not errors else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
