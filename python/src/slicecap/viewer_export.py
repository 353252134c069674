"""What the material viewer shows of a directory (slicecap-viewer DIR, docs/material-viewer.md):
the table of a `slicecap export` (its manifest's first table, the asked or default method) with
the fitted material the daemon wrote beside it, the SVBRDF maps folders inside it, or a
`slicecap fit BTF_DIR -o MAPS_DIR` folder itself.
"""

import json
import os
from dataclasses import dataclass

from slicecap.abrdf_exr import SlicecapFileError
from slicecap.paths import StrPath

MANIFEST_SUFFIX = "-manifest.json"  # io::fileSetManifestName: SESSION-manifest.json
MATERIAL_SUFFIX = "-material.json"  # material_export::sessionMaterial's material JSON
TABLE_INFIX = "-abrdf-"  # the daemon's tables: SESSION-abrdf-METHOD.exr
TEXTURE_SUFFIX = "-texture"  # the client's copy of the session's texture: DIR/SESSION-texture
MAPS_MANIFEST = "maps.json"  # what makes a folder a MAPS_DIR (slicecap.svbrdf_maps)


@dataclass(frozen=True)
class DirectoryContents:
    """What a directory holds for the viewer. `table` is None only for a MAPS_DIR (or a folder
    holding only maps folders); `found_by` says how the table was chosen, for the user."""

    directory: str
    table: str | None
    material: str | None
    other_tables: tuple[str, ...]
    maps_dirs: tuple[str, ...]
    found_by: str
    texture_dirs: tuple[str, ...] = ()  # SESSION-texture copies: frames, not yet a BTF or maps


def _manifests(directory: str) -> list[str]:
    return sorted(n for n in os.listdir(directory) if n.endswith(MANIFEST_SUFFIX))


def _listed_files(manifest: str) -> list[str]:
    """The names an export's manifest lists ({"format": 1, "set": ..., "files": [...]}, written
    by io::replaceFileSet in the order the export made them: the asked method's table first)."""
    try:
        with open(manifest, encoding="utf-8") as file:
            document = json.load(file)
    except OSError as e:
        raise SlicecapFileError(f"{manifest}: cannot read ({e.strerror})") from None
    except (ValueError, UnicodeDecodeError) as e:
        raise SlicecapFileError(f"{manifest}: not JSON ({e})") from None
    if not isinstance(document, dict) or document.get("format") != 1:
        raise SlicecapFileError(f"{manifest}: not an export manifest of format 1")
    files = document.get("files")
    if not isinstance(files, list) or not all(isinstance(f, str) for f in files):
        raise SlicecapFileError(f"{manifest}: \"files\" is not a list of names")
    return files


def _from_manifest(directory: str, manifest_name: str) -> tuple[list[str], str | None]:
    manifest = os.path.join(directory, manifest_name)
    listed = _listed_files(manifest)
    for name in listed:
        if os.path.basename(name) != name or not os.path.exists(os.path.join(directory, name)):
            raise SlicecapFileError(
                f"{manifest}: lists {name}, which is not in {directory} (an export copied in "
                "part?)")
    tables = [n for n in listed if n.endswith(".exr")]
    materials = [n for n in listed if n.endswith(MATERIAL_SUFFIX)]
    return tables, materials[0] if materials else None


def _material_by_name(directory: str, table: str) -> str | None:
    """The fit beside a table found by name: SESSION-material.json for SESSION-abrdf-M.exr (the
    daemon's names), else TABLE.json (as docs/material-fit.md's `slicecap fit T.exr -o T.json`)."""
    stem = os.path.splitext(table)[0]
    candidates = [stem + ".json"]
    if TABLE_INFIX in stem:
        candidates.insert(0, stem.split(TABLE_INFIX)[0] + MATERIAL_SUFFIX)
    for name in candidates:
        if os.path.isfile(os.path.join(directory, name)):
            return name
    return None


def _maps_dirs(directory: str) -> list[str]:
    # Not hidden folders: a texture fit killed before its swap leaves its staging folder
    # (.svbrdf-export.partial, io::replaceFileSet) with a maps.json of a set never put in place.
    return sorted(
        os.path.join(directory, entry.name) for entry in os.scandir(directory)
        if not entry.name.startswith(".") and entry.is_dir()
        and os.path.isfile(os.path.join(entry.path, MAPS_MANIFEST)))


def find_contents(directory: StrPath) -> DirectoryContents:
    """What DIRECTORY holds. With one SESSION-manifest.json (a `slicecap export` folder): the
    first table it lists and the material JSON it lists; without one: its only .exr and that
    table's fit by name (_material_by_name). Raises SlicecapFileError naming the directory or
    the manifest: not a directory, several manifests or (without one) several tables, a listed
    file missing, or nothing to show (no table and no maps folder)."""
    name = os.fspath(directory)
    if not os.path.isdir(name):
        raise SlicecapFileError(f"{name}: not a directory")
    if os.path.isfile(os.path.join(name, MAPS_MANIFEST)):
        return DirectoryContents(name, None, None, (), (name,), f"{MAPS_MANIFEST} (a MAPS_DIR)")
    try:
        manifests = _manifests(name)
        maps = _maps_dirs(name)
        if len(manifests) > 1:
            raise SlicecapFileError(
                f"{name}: holds the exports of several sessions ({', '.join(manifests)}): give "
                "one table, slicecap-viewer TABLE.exr --material MATERIAL.json")
        if manifests:
            tables, material = _from_manifest(name, manifests[0])
            found_by = manifests[0]
            looked_for = f"an .exr listed in {manifests[0]}"
        else:
            tables = sorted(n for n in os.listdir(name) if n.endswith(".exr"))
            material = _material_by_name(name, tables[0]) if len(tables) == 1 else None
            found_by = "file names (no *-manifest.json)"
            looked_for = f"*{MANIFEST_SUFFIX} or *.exr"
    except OSError as e:
        raise SlicecapFileError(f"{name}: cannot read ({e.strerror})") from None
    if len(tables) > 1 and not manifests:
        raise SlicecapFileError(
            f"{name}: {len(tables)} tables and no export manifest to say which is the export's "
            f"({', '.join(tables)}): give one, slicecap-viewer TABLE.exr")
    if not tables and not maps:
        raise SlicecapFileError(
            f"{name}: nothing to show: no ABRDF table ({looked_for}) and no SVBRDF maps folder "
            f"(a subfolder with {MAPS_MANIFEST})")
    return DirectoryContents(
        name,
        os.path.join(name, tables[0]) if tables else None,
        os.path.join(name, material) if material and tables else None,
        tuple(os.path.join(name, t) for t in tables[1:]),
        tuple(maps),
        found_by,
        tuple(sorted(os.path.join(name, n) for n in os.listdir(name)
                     if n.endswith(TEXTURE_SUFFIX) and os.path.isdir(os.path.join(name, n)))),
    )
