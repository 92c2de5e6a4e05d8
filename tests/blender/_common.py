"""What the Blender tests share (tests/blender/addon_test.py, fixture_test.py and
tests/consumers/blender_lights.py): their arguments, the Cycles set-up that makes a render
a measurement (direct light only, no filter, no denoising, linear 32-bit EXR), and the white
Lambertian surfaces they light.  Blender does not put a --python script's folder on
sys.path: each test adds this folder before `import _common`."""
import sys

import bpy


def luminance(r, g, b):
    return 0.2126 * r + 0.7152 * g + 0.0722 * b


def parse(argv, prog, defaults, required, lists=()):
    """The arguments after Blender's "--" as --name VALUE pairs into a copy of defaults (a
    dashed name is the key with underscores; a value is converted to its default's type; a
    key of `lists` collects every occurrence); exits naming an unknown or missing one."""
    argv = argv[argv.index("--") + 1:] if "--" in argv else []
    a = {k: list(v) if k in lists else v for k, v in defaults.items()}
    if len(argv) % 2:
        sys.exit("%s: %s needs a value" % (prog, argv[-1]))
    for k, v in zip(argv[::2], argv[1::2]):
        key = k.lstrip("-").replace("-", "_")
        if key not in a:
            sys.exit("%s: unknown argument %s" % (prog, k))
        if key in lists:
            a[key].append(v)
        else:
            a[key] = int(v) if isinstance(defaults[key], int) else v
    missing = [k for k in required if not a[k]]
    if missing:
        sys.exit("usage: blender ... --python %s.py -- %s (missing: %s)" % (
            prog, " ".join("--%s X" % k.replace("_", "-") for k in required),
            ", ".join(missing)))
    return a


def setup_cycles(scene, seed=1):
    """Cycles on the CPU as a measurement: every sample counted alike (no adaptive sampling,
    no denoising, no clamping, a one-pixel box filter), direct light only (the tests compare
    lighting, not bounces), an opaque film, a linear 32-bit EXR and the Standard view."""
    r = scene.render
    r.engine = "CYCLES"
    c = scene.cycles
    c.device = "CPU"
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.seed = seed
    c.pixel_filter_type = "BOX"
    c.filter_width = 1.0
    c.max_bounces = c.diffuse_bounces = c.glossy_bounces = 0
    c.transmission_bounces = c.volume_bounces = c.transparent_max_bounces = 0
    c.sample_clamp_direct = c.sample_clamp_indirect = 0.0
    r.film_transparent = False
    r.resolution_percentage = 100
    r.image_settings.file_format = "OPEN_EXR"
    r.image_settings.color_depth = "32"
    r.image_settings.exr_codec = "NONE"
    vs = scene.view_settings
    vs.view_transform = "Standard"
    vs.look = "None"
    vs.exposure = 0.0
    vs.gamma = 1.0


def white_lambert(name="lambert"):
    """A diffuse material of albedo 1 (Oren-Nayar roughness 0: Lambert's)."""
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nt = mat.node_tree
    nt.nodes.clear()
    d = nt.nodes.new("ShaderNodeBsdfDiffuse")
    d.inputs["Color"].default_value = (1, 1, 1, 1)
    d.inputs["Roughness"].default_value = 0.0
    o = nt.nodes.new("ShaderNodeOutputMaterial")
    nt.links.new(d.outputs["BSDF"], o.inputs["Surface"])
    return mat


def white_sphere(scene, name="sphere"):
    """A smooth unit sphere (128 x 64 segments) at the origin, white_lambert."""
    import bmesh  # noqa: PLC0415
    mesh = bpy.data.meshes.new(name)
    obj = bpy.data.objects.new(name, mesh)
    scene.collection.objects.link(obj)
    bm = bmesh.new()
    bmesh.ops.create_uvsphere(bm, u_segments=128, v_segments=64, radius=1.0)
    bm.to_mesh(mesh)
    bm.free()
    for p in mesh.polygons:
        p.use_smooth = True
    mesh.materials.append(white_lambert())
    return obj


def install_addon(zip_path, lumis_python):
    """An empty factory scene, then the add-on installed from its zip (into
    BLENDER_USER_SCRIPTS), enabled as a user enables it, its lumis package folder set in its
    preferences: the add-on's module."""
    import os  # noqa: PLC0415
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.preferences.addon_install(filepath=os.path.abspath(zip_path), overwrite=True)
    bpy.ops.preferences.addon_enable(module="lumis_lights")
    import lumis_lights  # noqa: PLC0415
    bpy.context.preferences.addons["lumis_lights"].preferences.lumis_path = lumis_python
    return lumis_lights
