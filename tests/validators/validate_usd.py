"""Validate a USD layer with USD's own validators (PyPI `usd-core`): every validator of
the UsdValidation registry (the framework `usdchecker` runs: stage metadata, shader
compliance with the shader registry, material encapsulation, …) over the opened stage.

Usage: python validate_usd.py FILE.usda
Prints one JSON line: {"valid": bool, "errors": [...], "materials": N, "shaders": N,
"previewSurfaces": N, "version": "0.26.x"}. Exit status 0 when valid, 1 when not, 2 when
the file does not open.
"""
import json
import sys

from pxr import Usd, UsdShade, UsdValidation


def main(path):
    stage = Usd.Stage.Open(path)
    if stage is None:
        print(json.dumps({"valid": False, "errors": ["the layer does not open"], "materials": 0}))
        return 2
    registry = UsdValidation.ValidationRegistry()
    validators = registry.GetOrLoadAllValidators()
    context = UsdValidation.ValidationContext(validators)
    found = context.Validate(stage)
    errors = [f"{e.GetName()}: {e.GetMessage()}" for e in found if e.GetType() == UsdValidation.ValidationErrorType.Error]
    materials = [p for p in stage.Traverse() if p.IsA(UsdShade.Material)]
    shaders = [UsdShade.Shader(p) for p in stage.Traverse() if p.IsA(UsdShade.Shader)]
    preview = [s for s in shaders if s.GetIdAttr().Get() == "UsdPreviewSurface"]
    # Every material's surface output reaches a shader.
    for material in materials:
        source = UsdShade.Material(material).ComputeSurfaceSource()
        if not source or not source[0]:
            errors.append(f"{material.GetPath()}: no surface shader")
    version = ".".join(str(v) for v in Usd.GetVersion())
    print(json.dumps({"valid": not errors, "errors": errors[:20], "materials": len(materials), "shaders": len(shaders), "previewSurfaces": len(preview), "version": version}))
    return 0 if not errors else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
