"""Validate a MaterialX document with the MaterialX Python package (PyPI `materialx`).

Usage: python validate_mtlx.py FILE.mtlx
Loads MaterialX's standard data libraries (so every node must match a nodedef), reads the
document, runs Document.validate(), and prints one JSON line:
{"valid": bool, "errors": "...", "materials": N, "version": "1.39.x"}. Exit status 0 when
valid, 1 when not, 2 on a read error.
"""
import json
import sys

import MaterialX as mx


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
    print(json.dumps({"valid": bool(valid), "errors": message, "materials": len(doc.getMaterialNodes()), "version": mx.getVersionString()}))
    return 0 if valid else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
