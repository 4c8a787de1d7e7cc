"""Validate a MaterialX document with the MaterialX Python package (PyPI `materialx`), and
generate GLSL for each of its materials.

Usage: python validate_mtlx.py FILE.mtlx
Loads MaterialX's standard data libraries (so every node must match a nodedef), reads the
document, runs Document.validate(), then generates a GLSL shader (MaterialX's own
GlslShaderGenerator) for every material's surface shader, and prints one JSON line:
{"valid": bool, "errors": "...", "materials": N, "version": "1.39.x",
 "glsl": {"<shader node category>": shaders generated}, "glsl_failures": [...]}.
Exit status 0 when valid and every shader generated, 1 when not, 2 on a read error.
"""
import json
import sys

import MaterialX as mx
import MaterialX.PyMaterialXGenGlsl as mx_gen_glsl
import MaterialX.PyMaterialXGenShader as mx_gen_shader


def generate_glsl(doc, stdlib):
    """GLSL for the surface shader of every material: {category: count}, failures."""
    generator = mx_gen_glsl.GlslShaderGenerator.create()
    context = mx_gen_shader.GenContext(generator)
    context.registerSourceCodeSearchPath(mx.getDefaultDataSearchPath())
    generated, failures = {}, []
    for material in doc.getMaterialNodes():
        shaders = mx.getShaderNodes(material)
        if not shaders:
            failures.append(material.getName() + ": no surface shader")
            continue
        shader = shaders[0]
        try:
            code = generator.generate(material.getName(), shader, context)
            pixel = code.getSourceCode(mx_gen_shader.PIXEL_STAGE)
            if not pixel or "void main" not in pixel:
                raise RuntimeError("no pixel stage")
            category = shader.getCategory()
            if category == "surface":  # a BSDF wrapped in a surface node: name the BSDF
                bsdf = shader.getConnectedNode("bsdf")
                category = bsdf.getCategory() if bsdf else category
            generated[category] = generated.get(category, 0) + 1
        except Exception as error:  # a generator error names the material
            failures.append(material.getName() + ": " + str(error)[:200])
    return generated, failures


def main(path):
    stdlib = mx.createDocument()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), stdlib)
    doc = mx.createDocument()
    try:
        mx.readFromXmlFile(doc, path)
    except mx.Exception as error:  # a malformed file
        print(json.dumps({"valid": False, "errors": "read: " + str(error), "materials": 0, "version": mx.getVersionString()}))
        return 2
    doc.setDataLibrary(stdlib)
    valid, message = doc.validate()
    # Every node must resolve to a standard nodedef (validate() alone accepts unknown categories).
    unresolved = [node.getName() for node in doc.getNodes() if node.getNodeDef() is None]
    if unresolved:
        valid = False
        message += "nodes without a nodedef: " + ", ".join(unresolved[:20])
    generated, failures = generate_glsl(doc, stdlib) if valid else ({}, [])
    print(
        json.dumps(
            {
                "valid": bool(valid),
                "errors": message,
                "materials": len(doc.getMaterialNodes()),
                "version": mx.getVersionString(),
                "glsl": generated,
                "glsl_failures": failures[:20],
            }
        )
    )
    return 0 if valid and not failures else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
