"""The pictures of docs/blender.md, made headless (Blender has no screen here, so the page shows
what the add-on makes, not its panels):

    scripts/blender-docs-images.sh          (builds the zip and runs this in Blender)

  docs/images/blender-hdri.png      a small scene lit by data/hdri/blender-sunrise.exr
  docs/images/blender-lamps.png     the same lit by 16 median-cut sun lamps from it ("Lights
                                    from World HDRI", the HDRI kept as the background only)
  docs/images/blender-fixture.png   tests/data/photometric/luxcore_asa_15m_r2.ies imported
                                    ("Import Photometric Fixture"), tilted over a floor

Cycles, 320 x 180, 64 samples, Filmic; both HDRI pictures share one exposure (the first's
mean), so the lamps' picture is comparable with the HDRI's.
"""
import math
import os
import sys

import bpy
from mathutils import Matrix, Vector


def args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    a = dict(zip([k.lstrip("-").replace("-", "_") for k in argv[::2]], argv[1::2]))
    for k in ("zip", "map", "fixture", "out", "lumis_python"):
        if k not in a:
            sys.exit("docs_images: --%s missing" % k.replace("_", "-"))
    return a


def material(name, rgb):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    m.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = (*rgb, 1)
    m.node_tree.nodes["Principled BSDF"].inputs["Roughness"].default_value = 0.6
    return m


def add(op, mat, **kw):
    op(**kw)
    o = bpy.context.object
    o.data.materials.append(mat)
    if hasattr(o.data, "polygons"):
        for p in o.data.polygons:
            p.use_smooth = True
    return o


def scene_objects(scene):
    add(bpy.ops.mesh.primitive_plane_add, material("floor", (0.6, 0.6, 0.6)), size=20)
    add(bpy.ops.mesh.primitive_uv_sphere_add, material("red", (0.7, 0.15, 0.1)),
        radius=0.6, location=(-0.9, 0, 0.6), segments=48, ring_count=24)
    add(bpy.ops.mesh.primitive_cube_add, material("white", (0.8, 0.8, 0.8)),
        size=0.9, location=(0.8, 0.4, 0.45), rotation=(0, 0, 0.5))
    add(bpy.ops.mesh.primitive_uv_sphere_add, material("blue", (0.1, 0.25, 0.7)),
        radius=0.35, location=(0.3, -1.0, 0.35), segments=32, ring_count=16)


def camera(scene, eye, target, lens=35):
    cam = bpy.data.objects.new("cam", bpy.data.cameras.new("cam"))
    scene.collection.objects.link(cam)
    cam.location = eye
    cam.rotation_euler = (Vector(target) - Vector(eye)).to_track_quat("-Z", "Y").to_euler()
    cam.data.lens = lens
    scene.camera = cam


def setup(scene):
    r = scene.render
    r.engine = "CYCLES"
    r.resolution_x, r.resolution_y, r.resolution_percentage = 320, 180, 100
    c = scene.cycles
    c.device = "CPU"
    c.samples = 64
    c.use_denoising = False
    c.seed = 1
    c.max_bounces = 4
    r.image_settings.file_format = "OPEN_EXR"
    r.image_settings.color_depth = "32"
    scene.view_settings.view_transform = "Filmic"


def render(scene, path_exr):
    scene.render.filepath = path_exr
    bpy.ops.render.render(write_still=True)
    img = bpy.data.images.load(path_exr, check_existing=False)
    return img


def mean_luminance(img):
    px = img.pixels[:]
    n = len(px) // 4
    return sum(0.2126 * px[4 * k] + 0.7152 * px[4 * k + 1] + 0.0722 * px[4 * k + 2]
               for k in range(n)) / n


def save_png(scene, img, path):
    s = scene.render.image_settings
    s.file_format, s.color_depth, s.compression = "PNG", "8", 100
    img.save_render(path, scene=scene)
    s.file_format, s.color_depth = "OPEN_EXR", "32"
    bpy.data.images.remove(img)
    print("wrote %s" % path)


def main():
    a = args()
    out = a["out"]
    tmp = os.path.join(out, ".exr")
    os.makedirs(tmp, exist_ok=True)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.preferences.addon_install(filepath=os.path.abspath(a["zip"]), overwrite=True)
    bpy.ops.preferences.addon_enable(module="lumis_lights")
    import lumis_lights  # noqa: PLC0415
    bpy.context.preferences.addons["lumis_lights"].preferences.lumis_path = a["lumis_python"]
    scene = bpy.context.scene
    setup(scene)
    scene_objects(scene)
    camera(scene, (4.5, -5.5, 3.0), (0, 0, 0.4))

    # 1. the HDRI (a Mapping node turned 40 degrees about z: the lamps must follow it)
    world = bpy.data.worlds.new("hdri")
    world.use_nodes = True
    nt = world.node_tree
    env = nt.nodes.new("ShaderNodeTexEnvironment")
    env.image = bpy.data.images.load(os.path.abspath(a["map"]))
    mapping = nt.nodes.new("ShaderNodeMapping")
    mapping.inputs["Rotation"].default_value = (0, 0, math.radians(40))
    coord = nt.nodes.new("ShaderNodeTexCoord")
    nt.links.new(coord.outputs["Generated"], mapping.inputs["Vector"])
    nt.links.new(mapping.outputs["Vector"], env.inputs["Vector"])
    bg = nt.nodes["Background"]
    nt.links.new(env.outputs["Color"], bg.inputs["Color"])
    scene.world = world
    img = render(scene, os.path.join(tmp, "hdri.exr"))
    scene.view_settings.exposure = math.log2(0.18 / max(mean_luminance(img), 1e-9))
    save_png(scene, img, os.path.join(out, "blender-hdri.png"))

    # 2. the lamps from it; the HDRI stays as the camera's background only, so the
    # picture shows the lamps' light and the same sky behind
    lumis_lights.lights_from_world(scene, "median-cut", 16, lumis_path=a["lumis_python"])
    lp = nt.nodes.new("ShaderNodeLightPath")
    mix = nt.nodes.new("ShaderNodeMixShader")
    black = nt.nodes.new("ShaderNodeBackground")
    black.inputs["Color"].default_value = (0, 0, 0, 1)
    out_node = nt.nodes["World Output"]
    nt.links.new(lp.outputs["Is Camera Ray"], mix.inputs["Fac"])
    nt.links.new(black.outputs["Background"], mix.inputs[1])
    nt.links.new(bg.outputs["Background"], mix.inputs[2])
    nt.links.new(mix.outputs["Shader"], out_node.inputs["Surface"])
    for o in bpy.data.collections["lumis lights"].objects:
        o.data.angle = math.radians(2.0)  # soft edges for the picture only (the test's are 0)
    img = render(scene, os.path.join(tmp, "lamps.exr"))
    save_png(scene, img, os.path.join(out, "blender-lamps.png"))

    # 3. a fixture: a road light 2.5 m up, tilted, over the same objects in the dark
    for o in list(bpy.data.collections["lumis lights"].objects):
        bpy.data.objects.remove(o)
    world.node_tree.links.remove(out_node.inputs["Surface"].links[0])
    lumis_lights.import_fixture(scene, a["fixture"], location=(-2.2, -0.6, 2.5),
                                aim=(0.5, 0.15, -1.0), lumis_path=a["lumis_python"])
    scene.view_settings.exposure = 0.0
    img = render(scene, os.path.join(tmp, "fixture.exr"))
    scene.view_settings.exposure = math.log2(0.18 / max(mean_luminance(img), 1e-9))
    save_png(scene, img, os.path.join(out, "blender-fixture.png"))
    for f in os.listdir(tmp):
        os.remove(os.path.join(tmp, f))
    os.rmdir(tmp)


main()
