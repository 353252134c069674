"""slicecap-export-merl MATERIAL.exr -o OUT.binary [--allow-anisotropic]
(or python -m slicecap.export_merl ...)

Writes an isotropic capture in the MERL binary format (slicecap.merl). Exit codes: 0 success,
1 failure (a message naming the input: unreadable, or anisotropic without the flag), 2 bad usage
(e.g. an output that is the input).
"""

import argparse
import sys
from collections.abc import Sequence

from slicecap.abrdf_exr import SlicecapFileError
from slicecap.materials import load_material
from slicecap.merl import MAX_ANISOTROPY, export_merl
from slicecap.paths import same_file

# The usage names what started it: the console script, or python -m (then this module is __main__).
PROG = "python -m slicecap.export_merl" if __name__ == "__main__" else "slicecap-export-merl"


def run(argv: Sequence[str]) -> int:
    parser = argparse.ArgumentParser(
        prog=PROG,
        description="Export an isotropic ABRDF EXR to MERL .binary",
    )
    parser.add_argument("material", help="the ABRDF EXR")
    parser.add_argument("-o", "--output", required=True, help="the MERL file to write")
    parser.add_argument(
        "--allow-anisotropic",
        action="store_true",
        help=f"export the azimuthal average of a table that changes by more than "
        f"{100 * MAX_ANISOTROPY:.0f} %% under rotation",
    )
    args = parser.parse_args(argv)
    if same_file(args.output, args.material):
        print(
            f"slicecap.export_merl: -o {args.output} is the material: it would be overwritten",
            file=sys.stderr,
        )
        return 2
    try:
        material = load_material(args.material)
        anisotropy = export_merl(args.output, material, allow_anisotropic=args.allow_anisotropic)
    except SlicecapFileError as e:
        print(f"slicecap.export_merl: {e}", file=sys.stderr)
        return 1
    except ValueError as e:
        print(f"slicecap.export_merl: {args.material}: {e}", file=sys.stderr)
        return 1
    print(f"wrote {args.output} (anisotropy {100 * anisotropy:.2f} %)")
    return 0


def main() -> None:
    sys.exit(run(sys.argv[1:]))


if __name__ == "__main__":
    main()
