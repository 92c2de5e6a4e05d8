"""lumis's built-in `bunny-plane` scene (without its GGX-plastic ball: see README.md), built
from scratch in Blender 3.4 and rendered by Cycles on the CPU, direct lighting only.

    blender -b --factory-startup -t 1 -P bench/cycles/scene.py -- \
        --map MAP.exr --spp N --out OUT.exr [--seed S] [--map-alone] [--size 160x120]

Prints `RENDER_SECONDS <s>`: the wall time of the render call alone (bpy.ops.render.render:
Cycles' scene sync -- BVH, image upload, the world's importance map -- and the sampling;
not Blender's start-up, the scene set-up nor writing the EXR).  Run with --debug-cycles
as well (before -P), Cycles logs `Render time (without synchronization): <s>`, the
sampling alone, which run.sh records.

Frames.  lumis is y up, Blender z up: a lumis point (x, y, z) is the Blender point
(x, -z, y) (a rotation of +90 degrees about x, so nothing is mirrored).  lumis looks a
direction up in its map at u = atan2(d_z, d_x) / 2pi, v = theta / pi (row 0 = zenith);
Cycles' equirectangular lookup of a Blender direction b is u = 1/2 - atan2(b_y, b_x) / 2pi,
v = 1 - theta / pi (image row 0 at the bottom, so the file's first row is again the zenith).
With b = (x, -z, y): atan2(b_y, b_x) = -phi, so Cycles would read u_lumis + 1/2; a Mapping
node turning the lookup direction by 180 degrees about z (b -> (-b_x, -b_y, b_z)) takes
the half turn out: u_cycles = u_lumis exactly, no mirror (checked by --map-alone).
"""

import math
import os
import sys
import time

import bpy

HERE = os.path.dirname(os.path.abspath(__file__))


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else []
    a = {"map": None, "spp": 16, "out": None, "seed": 0, "map_alone": False, "size": "160x120",
         "mesh": os.path.join(HERE, "bunny-assimp.obj"), "no_env_rotation": False,
         "lumis_scene": None, "bounces": 0}
    i = 0
    while i < len(argv):
        k = argv[i]
        if k == "--map-alone":
            a["map_alone"] = True
        elif k == "--no-env-rotation":  # for the orientation check only
            a["no_env_rotation"] = True
        elif k in ("--map", "--spp", "--out", "--seed", "--size", "--mesh", "--lumis-scene",
                   "--bounces"):
            i += 1
            a[k[2:].replace("-", "_")] = argv[i]
        else:
            sys.exit("scene.py: unknown argument %r" % k)
        i += 1
    if not a["map"] or not a["out"]:
        sys.exit("scene.py: --map and --out are required")
    a["spp"] = int(a["spp"])
    a["seed"] = int(a["seed"])
    a["bounces"] = int(a["bounces"])
    return a


def to_blender(p):
    """lumis (y up) -> Blender (z up)."""
    return (p[0], -p[2], p[1])


def read_obj(path):
    verts, faces = [], []
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                verts.append(tuple(float(t) for t in line.split()[1:4]))
            elif line.startswith("f "):
                faces.append(tuple(int(t.split("/")[0]) - 1 for t in line.split()[1:4]))
    return verts, faces


def bunny_vertices(verts, height=1.1, x=-0.55, z=0.0, yaw_deg=20.0):
    """builtin.c's embedded_mesh(..., 1.1, -0.55, 0, 20, centre 0): scaled to `height`,
    lowest vertex on y = 0, turned by yaw about +y (R_y of lumis__rotation_deg), moved by
    (x, z)."""
    lo = min(v[1] for v in verts)
    hi = max(v[1] for v in verts)
    s = height / (hi - lo)
    c, sn = math.cos(math.radians(yaw_deg)), math.sin(math.radians(yaw_deg))
    t = (x, -lo * s, z)
    out = []
    for vx, vy, vz in verts:
        px, py, pz = s * vx, s * vy, s * vz
        out.append((c * px + sn * pz + t[0], py + t[1], -sn * px + c * pz + t[2]))
    return out


def lambert(name, albedo):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    nt = m.node_tree
    nt.nodes.clear()
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    d = nt.nodes.new("ShaderNodeBsdfDiffuse")
    d.inputs["Color"].default_value = (albedo, albedo, albedo, 1.0)
    d.inputs["Roughness"].default_value = 0.0  # Lambert (no Oren-Nayar)
    nt.links.new(d.outputs["BSDF"], out.inputs["Surface"])
    return m


def add_mesh(name, verts_lumis, faces, material):
    me = bpy.data.meshes.new(name)
    me.from_pydata([to_blender(v) for v in verts_lumis], [], faces)
    me.update()
    for p in me.polygons:
        p.use_smooth = False  # lumis shades meshes with geometric normals
    me.materials.append(material)
    ob = bpy.data.objects.new(name, me)
    bpy.context.scene.collection.objects.link(ob)
    # Only acts on smooth-shaded triangles; zero anyway so nothing moves the shadow rays.
    if hasattr(ob, "cycles") and hasattr(ob.cycles, "shadow_terminator_geometry_offset"):
        ob.cycles.shadow_terminator_geometry_offset = 0.0
    return ob


def glossy(name, color, alpha):
    """Cycles' Glossy BSDF, GGX: lumis's `glossy` material (docs/bsdf.md) term for term;
    Cycles squares the node's roughness, so roughness = sqrt(alpha)."""
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    nt = m.node_tree
    nt.nodes.clear()
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    g = nt.nodes.new("ShaderNodeBsdfGlossy")
    g.distribution = "GGX"
    g.inputs["Color"].default_value = (color[0], color[1], color[2], 1.0)
    g.inputs["Roughness"].default_value = math.sqrt(alpha)
    nt.links.new(g.outputs["BSDF"], out.inputs["Surface"])
    return m


def lumis_transform(tr):
    """A lumis scene file's transform (scale, then Rz Ry Rx, then translate) as a function
    of a lumis point."""
    if not tr:
        return lambda p: p
    s = tr.get("scale", 1.0)
    s = (s, s, s) if isinstance(s, (int, float)) else tuple(s)
    rx, ry, rz = (math.radians(d) for d in tr.get("rotate_deg", (0, 0, 0)))
    t = tr.get("translate", (0, 0, 0))

    def rot(p):
        x, y, z = p
        y, z = math.cos(rx) * y - math.sin(rx) * z, math.sin(rx) * y + math.cos(rx) * z
        x, z = math.cos(ry) * x + math.sin(ry) * z, -math.sin(ry) * x + math.cos(ry) * z
        x, y = math.cos(rz) * x - math.sin(rz) * y, math.sin(rz) * x + math.cos(rz) * y
        return (x, y, z)

    return lambda p: tuple(a + b for a, b in zip(rot(tuple(q * k for q, k in zip(p, s))), t))


def lumis_material(name, m):
    if m["type"] == "lambert":
        a = m.get("albedo", (0.8, 0.8, 0.8))
        if not a[0] == a[1] == a[2]:
            sys.exit("scene.py: %s: grey albedos only" % name)
        return lambert(name, a[0])
    if m["type"] == "glossy":
        if "alpha_x" in m or "alpha_y" in m:
            sys.exit("scene.py: %s: isotropic glossy only" % name)
        return glossy(name, m.get("color", (0.9, 0.9, 0.9)), m.get("alpha", 0.1))
    sys.exit("scene.py: %s: material %r has no exact Cycles counterpart" % (name, m["type"]))


def load_lumis_scene(path):
    """The camera and objects of a lumis scene file (meshes and +y planes; materials
    lambert and glossy), built in Blender.  The bunny's glb is read as bunny-assimp.obj
    (the same triangles, decoded by assimp as lumis does)."""
    import json

    with open(path) as f:
        sc = json.load(f)
    base = os.path.dirname(os.path.abspath(path))
    for k, o in enumerate(sc["objects"]):
        name = "obj%d" % k
        mat = lumis_material(name, o["material"])
        if o["type"] == "mesh":
            file = o["file"]
            file = (os.path.join(HERE, "bunny-assimp.obj") if file.endswith("bunny.glb")
                    else os.path.join(base, file))
            verts, faces = read_obj(file)
            x = lumis_transform(o.get("transform"))
            add_mesh(name, [x(v) for v in verts], faces, mat)
        elif o["type"] == "plane" and tuple(o["normal"]) == (0, 1, 0):
            g, (px, py, pz) = o["size"] / 2.0, o["point"]
            add_mesh(name, [(px - g, py, pz + g), (px + g, py, pz + g), (px + g, py, pz - g),
                            (px - g, py, pz - g)], [(0, 1, 2, 3)], mat)
        else:
            sys.exit("scene.py: objects[%d]: only meshes and +y planes" % k)
    return sc["camera"]


def look_at_matrix(eye, target, up):
    """Blender camera matrix_world: local -z along the view, +y up, +x right."""
    from mathutils import Matrix, Vector

    e, t, u = Vector(eye), Vector(target), Vector(up)
    fwd = (t - e).normalized()
    right = fwd.cross(u).normalized()
    upv = right.cross(fwd)
    m = Matrix.Identity(4)
    for r in range(3):
        m[r][0], m[r][1], m[r][2], m[r][3] = right[r], upv[r], -fwd[r], e[r]
    return m


def main():
    a = parse_args()
    w, h = (int(t) for t in a["size"].lower().split("x"))
    scene = bpy.context.scene
    # Start from the factory scene, emptied (its cube, lamp and camera removed).
    for ob in list(bpy.data.objects):
        bpy.data.objects.remove(ob, do_unlink=True)

    # --- render settings ---
    r = scene.render
    r.engine = "CYCLES"
    r.resolution_x, r.resolution_y, r.resolution_percentage = w, h, 100
    r.pixel_aspect_x = r.pixel_aspect_y = 1.0
    r.film_transparent = False
    r.use_compositing = False
    r.use_sequencer = False
    r.dither_intensity = 0.0
    r.use_motion_blur = False
    c = scene.cycles
    c.device = "CPU"
    c.samples = a["spp"]
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.use_preview_denoising = False
    c.seed = a["seed"]
    c.use_animated_seed = False
    c.pixel_filter_type = "BOX"
    c.filter_width = 1.0
    # Path tracing with --bounces N: total, diffuse and glossy N (lumis --bounces N: direct
    # light at the camera's hit and at N further vertices); the others 0.
    c.max_bounces = a["bounces"]
    c.diffuse_bounces = a["bounces"]
    c.glossy_bounces = a["bounces"]
    # Filter Glossy (default 1) widens glossy lobes after a diffuse bounce: off, so the
    # glossy material stays the same BSDF on every path; caustics stay on (the default).
    c.blur_glossy = 0.0
    c.caustics_reflective = True
    c.caustics_refractive = True
    c.transmission_bounces = 0
    c.volume_bounces = 0
    c.transparent_max_bounces = 0
    c.sample_clamp_direct = 0.0
    c.sample_clamp_indirect = 0.0
    c.use_auto_tile = False  # one 160x120 image is one tile anyway
    if hasattr(c, "time_limit"):
        c.time_limit = 0.0
    # Cycles 3.4's default sampling pattern (progressive multi-jitter); checked, not set.
    print("SAMPLING_PATTERN", getattr(c, "sampling_pattern", "?"))
    if hasattr(c, "use_light_tree"):
        print("LIGHT_TREE", c.use_light_tree)

    vs = scene.view_settings
    vs.view_transform = "Standard"
    vs.look = "None"
    vs.exposure = 0.0
    vs.gamma = 1.0
    vs.use_curve_mapping = False
    im = r.image_settings
    im.file_format = "OPEN_EXR"
    im.color_mode = "RGB"
    im.color_depth = "32"
    im.exr_codec = "ZIP"

    cam_l = {"eye": (0, 1.3, 4.0), "look_at": (0.1, 0.45, 0.0), "up": (0, 1, 0), "fov_deg": 35.0}
    if a["lumis_scene"] and not a["map_alone"]:
        cam_l = load_lumis_scene(a["lumis_scene"])
    # --- camera: lumis (eye (0, 1.3, 4), look at (0.1, 0.45, 0), up +y, vertical fov 35,
    # or the scene file's) ---
    cd = bpy.data.cameras.new("cam")
    cd.type = "PERSP"
    cd.sensor_fit = "VERTICAL"
    cd.angle_y = math.radians(cam_l.get("fov_deg", 40.0))
    cd.shift_x = cd.shift_y = 0.0
    cd.clip_start = 1e-4
    cd.clip_end = 1e6  # the ground is 200 wide: the default 100 would cut it
    cd.dof.use_dof = False
    cam = bpy.data.objects.new("cam", cd)
    scene.collection.objects.link(cam)
    cam.matrix_world = look_at_matrix(to_blender(cam_l["eye"]), to_blender(cam_l["look_at"]),
                                      to_blender(cam_l.get("up", (0, 1, 0))))
    scene.camera = cam

    # --- objects ---
    if not a["map_alone"] and not a["lumis_scene"]:
        verts, faces = read_obj(a["mesh"])
        add_mesh("bunny", bunny_vertices(verts), faces, lambert("bunny", 0.75))
        # lumis's ground_plane: a square of side 200 about the origin, normal +y, edges
        # along x and z (basis() of n = +y gives t = +x, b = -z).
        g = 100.0
        add_mesh("ground", [(-g, 0, g), (g, 0, g), (g, 0, -g), (-g, 0, -g)], [(0, 1, 2, 3)],
                 lambert("ground", 0.5))

    # --- world: the map, nearest-pixel lookups, turned into lumis's frame ---
    world = bpy.data.worlds.new("env")
    scene.world = world
    world.use_nodes = True
    nt = world.node_tree
    nt.nodes.clear()
    img = bpy.data.images.load(os.path.abspath(a["map"]))
    img.colorspace_settings.name = "Linear"
    tc = nt.nodes.new("ShaderNodeTexCoord")
    mp = nt.nodes.new("ShaderNodeMapping")
    mp.vector_type = "POINT"
    mp.inputs["Rotation"].default_value = (0.0, 0.0,
                                           0.0 if a["no_env_rotation"] else math.pi)
    env = nt.nodes.new("ShaderNodeTexEnvironment")
    env.image = img
    env.interpolation = "Closest"
    env.projection = "EQUIRECTANGULAR"
    bg = nt.nodes.new("ShaderNodeBackground")
    bg.inputs["Strength"].default_value = 1.0
    wo = nt.nodes.new("ShaderNodeOutputWorld")
    nt.links.new(tc.outputs["Generated"], mp.inputs["Vector"])
    nt.links.new(mp.outputs["Vector"], env.inputs["Vector"])
    nt.links.new(env.outputs["Color"], bg.inputs["Color"])
    nt.links.new(bg.outputs["Background"], wo.inputs["Surface"])
    wc = world.cycles
    print("WORLD_SAMPLING", getattr(wc, "sampling_method", "?"),
          getattr(wc, "sample_map_resolution", "?"))

    # --- render, timed ---
    t0 = time.perf_counter()
    bpy.ops.render.render(write_still=False)
    dt = time.perf_counter() - t0
    bpy.data.images["Render Result"].save_render(os.path.abspath(a["out"]))
    print("RENDER_SECONDS %.6f" % dt)


main()
