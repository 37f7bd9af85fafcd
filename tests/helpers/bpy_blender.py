#!/usr/bin/env python3
"""A stand-in for the `blender` executable in farm tests: Blender 4.5 as a Python module (bpy).

Debian's Blender 3.4 has no Alembic and the farm's bake needs it, so the job templates are
run with their Blender parameter pointing here. It takes the part of Blender's command line
the templates use and does what Blender does with it:

    bpy_blender.py -b FILE [--python-exit-code N] --python-expr EXPR [-- ARGS...]

(opens FILE, runs EXPR with sys.argv as Blender would leave it, exits N when EXPR raises).
"""

import sys
import traceback


def main(argv: list[str]) -> int:
    rest = argv[argv.index("--"):] if "--" in argv else []
    options = argv[: len(argv) - len(rest)]
    blend = expr = None
    exit_code = 0
    i = 0
    while i < len(options):
        flag = options[i]
        if flag in ("-b", "--background"):
            if i + 1 < len(options) and not options[i + 1].startswith("-"):
                blend, i = options[i + 1], i + 1
        elif flag == "--python-exit-code":
            exit_code, i = int(options[i + 1]), i + 1
        elif flag == "--python-expr":
            expr, i = options[i + 1], i + 1
        elif flag == "--factory-startup":
            pass
        else:
            print(f"bpy_blender: unsupported option {flag}", file=sys.stderr)
            return 2
        i += 1
    import bpy

    if blend:
        bpy.ops.wm.open_mainfile(filepath=blend)
    sys.argv = ["blender", *argv]
    try:
        exec(compile(expr or "", "<string>", "exec"), {"__name__": "__main__"})
    except Exception:
        traceback.print_exc()
        return exit_code
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
