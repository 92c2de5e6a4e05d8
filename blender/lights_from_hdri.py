"""The add-on's headless entry point (docs/blender.md):

    blender -b [SCENE.blend] --python blender/lights_from_hdri.py -- \\
        [--hdri MAP] [--rotation-deg X,Y,Z] [--method M] [-k K] [--param P] [--remove-hdri]
        [--lumis-python DIR] [--save OUT.blend] [--json REPORT.json]

Adds the sun lamps of "Lights from World HDRI" to the scene's world HDRI (with --hdri: a
world made with that map as its Environment Texture, behind a Mapping node of the given
rotation), prints the report and saves the file.  Uses the installed add-on when enabled,
else the lumis_lights folder beside this script.  Exit 0 done, 1 refused (the message on
stderr).
"""
import json
import os
import sys

import bpy


def parse(argv):
    argv = argv[argv.index("--") + 1:] if "--" in argv else []
    a = {"hdri": None, "rotation": (0.0, 0.0, 0.0), "method": "median-cut", "k": 16,
         "param": "", "remove": False, "lumis_python": "", "save": None, "json": None}
    i = 0
    while i < len(argv):
        k = argv[i]
        v = argv[i + 1] if i + 1 < len(argv) else None
        if k == "--remove-hdri":
            a["remove"] = True
            i += 1
            continue
        if v is None:
            sys.exit("lights_from_hdri: %s needs a value" % k)
        if k == "--hdri":
            a["hdri"] = v
        elif k == "--rotation-deg":
            a["rotation"] = tuple(float(c) for c in v.split(","))
            if len(a["rotation"]) != 3:
                sys.exit("lights_from_hdri: --rotation-deg wants X,Y,Z, got %s" % v)
        elif k == "--method":
            a["method"] = v
        elif k in ("-k", "--count"):
            a["k"] = int(v)
        elif k == "--param":
            a["param"] = v
        elif k == "--lumis-python":
            a["lumis_python"] = v
        elif k == "--save":
            a["save"] = v
        elif k == "--json":
            a["json"] = v
        else:
            sys.exit("lights_from_hdri: unknown argument %s" % k)
        i += 2
    return a


def main():
    a = parse(sys.argv)
    try:
        import lumis_lights  # noqa: PLC0415 - the installed add-on
    except ImportError:
        sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
        import lumis_lights  # noqa: PLC0415
    scene = bpy.context.scene
    if a["hdri"]:
        lumis_lights.world_with_hdri(scene, a["hdri"], a["rotation"])
    try:
        r = lumis_lights.lights_from_world(scene, a["method"], a["k"], a["param"], a["remove"],
                                           True, a["lumis_python"])
    except lumis_lights.LumisError as e:
        sys.stderr.write("lights_from_hdri: %s\n" % e)
        sys.stderr.flush()
        os._exit(1)
    print("lumis: %d sun lamps by %s from %s; irradiance on an upward surface: lights %.6g, "
          "map %.6g" % (r["count"], r["method"], r["source"], r["irradiance_up"]["lights"],
                        r["irradiance_up"]["map"]))
    if a["json"]:
        with open(a["json"], "w") as f:
            json.dump(r, f, indent=1)
    if a["save"]:
        bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(a["save"]))
    sys.stdout.flush()
    os._exit(0)  # Blender's own exit would return 0 whatever happened


main()
