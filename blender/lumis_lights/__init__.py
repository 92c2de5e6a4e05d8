"""lumis lights: sun lamps from the world's HDRI (docs/blender.md).

"Lights from world HDRI" reads the world's Environment Texture (its image, the Background's
strength and the rotation of a Mapping node in front of it), builds K lights with a lumis
light-set method through the lumis Python package (python/lumis; Debian's Blender runs the
system's Python 3, where python3-cffi and python3-numpy are, so the package loads inside it),
and adds one sun lamp per light: pointing where the light is as Blender shows the HDRI,
colour and strength its irradiance in W/m^2 for a map in W/(m^2 sr) (Blender's sun
strength), so that a diffuse surface under the suns receives what the lights give it.

"Import Photometric Fixture" reads an IES LM-63 or EULUMDAT file with lumis's photometric
model and adds a point lamp carrying Cycles' IES Texture, its table resampled from lumis's
intensity in Blender's own reading of IES angles, its power the fixture's flux at 683 lm/W,
aimed by lumis's rule for the file's type (docs/blender.md, "Photometric fixtures").

Headless: blender/lights_from_hdri.py, or from any script with the add-on enabled:

    import lumis_lights
    lumis_lights.lights_from_world(bpy.context.scene, method="median-cut", count=16)
    lumis_lights.import_fixture(bpy.context.scene, "spot.ies", location=(0, 0, 3))
"""

import math
import os
import sys

import bpy
from bpy.props import (BoolProperty, EnumProperty, FloatProperty, FloatVectorProperty,
                       IntProperty, StringProperty)
from mathutils import Euler, Matrix, Vector

bl_info = {
    "name": "lumis lights",
    "author": "lumis",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "Add > Light > Lights from World HDRI / Photometric Fixture; World Properties "
                "> lumis lights; File > Import > Photometric Fixture",
    "description": "Sun lamps that reproduce the world HDRI's irradiance (lumis light sets); "
                   "IES/EULUMDAT fixtures as lamps with lumis's photometric model",
    "category": "Lighting",
}

COLLECTION = "lumis lights"
# What a light set is built with when the lumis package cannot be asked (the enum's items
# are read from lumis.light_methods() once it loads).
_FALLBACK_METHODS = ("median-cut", "variance-min", "wu", "kmeans", "penrose")


class LumisError(RuntimeError):
    """What the add-on refuses (the operator reports it; the headless script exits 1)."""


def import_lumis(extra_path=""):
    """The lumis Python package: already importable (`make install`), or from
    extra_path, the add-on's preference or $LUMIS_PYTHON_PATH (a folder holding lumis/,
    e.g. the source tree's python/)."""
    try:
        import lumis  # noqa: PLC0415
        return lumis
    except ImportError as first:
        tried = []
        for d in (extra_path, os.environ.get("LUMIS_PYTHON_PATH", "")):
            if d and os.path.isdir(os.path.join(d, "lumis")) and d not in sys.path:
                sys.path.insert(0, d)
                tried.append(d)
                try:
                    import lumis  # noqa: PLC0415
                    return lumis
                except ImportError as e:
                    first = e
        raise LumisError(
            "cannot import the lumis Python package (%s; looked also in %s): install it "
            "(make install) or set the add-on's 'lumis package folder' or "
            "LUMIS_PYTHON_PATH to the folder that holds lumis/" %
            (first, ", ".join(tried) or "no other folder")) from first


# ---- frames -------------------------------------------------------------------------------
#
# lumis's frame is y up, a map pixel at azimuth p (column u = p / 2 pi) seen along
# (sin t cos p, cos t, sin t sin p).  Cycles' environment texture (direction_to_
# equirectangular) reads a Blender direction b (z up) at u = 1/2 - atan2(b.y, b.x) / 2 pi,
# v = 1 - acos(b.z) / pi from the bottom.  b = (-x, z, y) puts every lumis direction on its own
# pixel: atan2(sin p, -cos p) = pi - p gives u = p / 2 pi, and acos(cos t) = t.  (The glTF
# export's engine frame (-x, y, -z) followed by the glTF importer's (x, -z, y) is the same map;
# docs/lights-export.md.)

def lumis_to_blender(d):
    return Vector((-d[0], d[2], d[1]))


def blender_to_lumis(b):
    return (-b[0], b[2], b[1])


def mapping_matrix(node):
    """M with world direction = M (texture direction) for the Mapping node in front of the
    Environment Texture (None: identity).  A Point, Vector or Normal mapping looks the
    texture up at R d (R = Rz Ry Rx of its rotation), so a texture direction b appears at
    R^T b; a Texture mapping is the inverse transform: b appears at R b."""
    if node is None:
        return Matrix.Identity(3)
    rot = node.inputs["Rotation"]
    scale = node.inputs["Scale"]
    if rot.is_linked or scale.is_linked or node.inputs["Location"].is_linked:
        raise LumisError("the Mapping node '%s' has linked inputs: only constant rotations are "
                         "read" % node.name)
    s = tuple(scale.default_value)
    if min(s) <= 0 or max(s) - min(s) > 1e-6 * max(s):
        raise LumisError("the Mapping node '%s' has scale %s: only a uniform positive scale "
                         "keeps directions" % (node.name, s))
    if node.vector_type == "POINT" and any(abs(c) > 0 for c in node.inputs["Location"].default_value):
        raise LumisError("the Mapping node '%s' has a location: an environment has none "
                         "(set it to 0)" % node.name)
    R = Euler(tuple(rot.default_value), "XYZ").to_matrix()
    return R.copy() if node.vector_type == "TEXTURE" else R.transposed()


def _source(socket):
    if not socket.is_linked:
        return None
    return socket.links[0].from_node


def find_environment(world):
    """(Environment Texture node, Background node, Mapping node or None) of the world's active
    output, or LumisError saying what is not there."""
    if world is None or not world.use_nodes:
        raise LumisError("the scene has no world with nodes: add an Environment Texture to "
                         "the world")
    outs = [n for n in world.node_tree.nodes if n.type == "OUTPUT_WORLD"]
    out = next((n for n in outs if n.is_active_output), outs[0] if outs else None)
    if out is None:
        raise LumisError("the world '%s' has no World Output node" % world.name)
    bg = _source(out.inputs["Surface"])
    if bg is None or bg.type != "BACKGROUND":
        raise LumisError("the world '%s': its output's Surface is not a Background node" % world.name)
    env = _source(bg.inputs["Color"])
    if env is None or env.type != "TEX_ENVIRONMENT":
        raise LumisError("the world '%s': its Background's Color is not an Environment "
                         "Texture (link one directly)" % world.name)
    if env.image is None:
        raise LumisError("the Environment Texture '%s' has no image" % env.name)
    if env.projection != "EQUIRECTANGULAR":
        raise LumisError("the Environment Texture '%s' is %s: lumis reads equirectangular maps"
                         % (env.name, env.projection))
    mapping = _source(env.inputs["Vector"])
    if mapping is not None and mapping.type != "MAPPING":
        # a Texture Coordinate node straight in: Generated is the view direction
        if mapping.type != "TEX_COORD":
            raise LumisError("the Environment Texture '%s' takes its vector from a %s node: "
                             "only a Mapping node (or none) is understood" % (env.name, mapping.type))
        mapping = None
    if bg.inputs["Strength"].is_linked:
        raise LumisError("the Background's Strength is linked: only a constant is read")
    return env, bg, mapping


def _image_map(lumis, image):
    """The map as lumis reads it: the image's file when lumis reads its format, else its
    pixels as Blender holds them (packed or generated images; RGBA rows bottom up)."""
    path = bpy.path.abspath(image.filepath, library=image.library) if image.filepath else ""
    if path and os.path.isfile(path) and image.packed_file is None:
        try:
            return lumis.read_map(path), path
        except lumis.Error:
            pass  # a format lumis does not read (PNG, JPEG...): Blender's own pixels
    import numpy as np  # noqa: PLC0415
    w, h = image.size
    if w < 1 or h < 1:
        raise LumisError("the image '%s' has no pixels" % image.name)
    px = np.empty(w * h * 4, dtype=np.float32)
    image.pixels.foreach_get(px)
    rgb = px.reshape(h, w, 4)[::-1, :, :3]  # row 0 the top (the zenith)
    return lumis.Map(np.ascontiguousarray(rgb), source=image.name), image.name


def lights_from_world(scene, method="median-cut", count=16, params="", remove_hdri=False,
                      replace=True, lumis_path=""):
    """Adds one sun lamp per light of a lumis light set of the world's HDRI to the collection
    "lumis lights" (emptied first with replace).  Returns a dict: the method, K, the map's
    source, the lamps' names, their directions (Blender frame) and strengths, the lights'
    and the map's irradiance on an upward surface (luminance, lumis_light_set_irradiance)."""
    lumis = import_lumis(lumis_path)
    env, bg, mapping = find_environment(scene.world)
    M = mapping_matrix(mapping)
    strength = float(bg.inputs["Strength"].default_value)
    lmap, source = _image_map(lumis, env.image)
    with lmap:
        try:
            ls = lumis.lights(lmap, method, count=count, params=params or None)
        except lumis.Error as e:
            raise LumisError("lumis lights %s: %s" % (method, e.message)) from e
        with ls:
            L = ls.lights()
            up_tex = blender_to_lumis(M.transposed() @ Vector((0, 0, 1)))
            e_set, e_map = ls.irradiance(up_tex)
            info = ls.info()

    coll = bpy.data.collections.get(COLLECTION)
    if coll is None:
        coll = bpy.data.collections.new(COLLECTION)
    if coll.name not in scene.collection.children:
        scene.collection.children.link(coll)
    if replace:
        for o in list(coll.objects):
            data = o.data
            bpy.data.objects.remove(o)
            if data is not None and data.users == 0:
                bpy.data.lights.remove(data)

    names, dirs, strengths = [], [], []
    for k, light in enumerate(L):
        power = [float(c) * strength for c in light["power"]]
        peak = max(power)
        if not peak > 0:
            continue
        d = (M @ lumis_to_blender(light["direction"])).normalized()
        data = bpy.data.lights.new("lumis %s %d" % (method, k), "SUN")
        data.color = [c / peak for c in power]  # colour x strength == power, as the glTF export
        data.energy = peak                       # W/m^2 on a surface facing the sun
        data.angle = 0.0                          # a point light, as lumis's lights
        obj = bpy.data.objects.new(data.name, data)
        # a sun shines along its local -Z: its +Z points at the light
        obj.rotation_euler = d.to_track_quat("Z", "Y").to_euler()
        obj["lumis_method"] = method
        obj["lumis_light"] = k
        obj["lumis_solid_angle"] = float(light["solid_angle"])
        coll.objects.link(obj)
        names.append(obj.name)
        dirs.append(tuple(d))
        strengths.append(peak)

    if remove_hdri:
        # the HDRI no longer lights the scene (nor is seen): the Environment Texture stays in
        # the node tree, unlinked, to be linked again by hand
        for link in list(bg.inputs["Color"].links):
            scene.world.node_tree.links.remove(link)
        bg.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
    return {"method": method, "count": len(names), "source": source, "lamps": names,
            "directions": dirs, "strengths": strengths, "strength": strength,
            "irradiance_up": {"lights": e_set * strength, "map": e_map * strength},
            "build_ms": info["build_ms"], "params": params}


# ---- photometric fixtures ---------------------------------------------------------------
#
# Cycles' IES Texture on a point lamp (Blender 3.4, util/ies.cpp and svm/ies.h) looks its table
# up with the lamp's local direction b (from the lamp to the lit point) at v = acos(-b.z) and
# h = atan2(b.x, b.y) + pi: v from the lamp's -Z as lumis's gamma, but h = 0 along local -y and
# h = 90 along -x, where lumis puts C0 along +x and C90 along +y.  Its values are candela times
# the multiplier and the ballast factors, times 4 pi / 177.83 (D65's lm/W), and the lamp then
# emits power / (4 pi) x that value W/sr: power P W gives I / 177.83 x P W/sr.  So the add-on
# writes its own table: at Blender's (h, v) the intensity lumis gives the local direction
# b(h, v), times 177.83 / flux, with the lamp's power the flux / LUMENS_PER_WATT: the lamp
# emits lumis's intensity / LUMENS_PER_WATT W/sr in every direction, its total power the
# fixture's flux in watts.  The lamp's local frame is then lumis's luminaire frame (aim -z,
# C0 or the top +x), placed by lumis's rotation R through the add-on's frame map F
# (lumis_to_blender): matrix_world = F R.

LUMENS_PER_WATT = 683.0     # the convention: lm per W at 555 nm (docs/blender.md)
CYCLES_IES_LM_PER_W = 177.83  # what Cycles' IES node divides candela by (util/ies.cpp)
FIXTURES = "lumis fixtures"
# the resampled table: gamma every 1 degree over the whole sphere, C every 2.5 degrees
_GRID_V, _GRID_H = 1.0, 2.5

F_LUMIS_TO_BLENDER = Matrix(((-1, 0, 0), (0, 0, 1), (0, 1, 0)))


def _blender_ies_direction(h_deg, v_deg):
    """The lamp-local direction at which Cycles reads its table's (h, v) (above)."""
    h, v = math.radians(h_deg), math.radians(v_deg)
    return (-math.sin(v) * math.sin(h), -math.sin(v) * math.cos(h), -math.cos(v))


def fixture_ies_text(ph, name="lumis"):
    """An LM-63-2002 table (type C, v 0-180, h 0-360) that Cycles' IES Texture reads as ph's
    intensity per unit flux times 177.83 (above), for a lamp whose power is the flux in W."""
    import numpy as np  # noqa: PLC0415
    vs = np.arange(0.0, 180.0 + 1e-9, _GRID_V)
    hs = np.arange(0.0, 360.0 + 1e-9, _GRID_H)
    dirs = np.array([_blender_ies_direction(h, v) for h in hs for v in vs], dtype=np.float32)
    scale = CYCLES_IES_LM_PER_W / ph.flux
    cd = ph.intensity(dirs).reshape(len(hs), len(vs)) * scale
    lines = ["IESNA:LM-63-2002", "[TEST] lumis resampled: Cycles' angles, candela x 177.83 / flux",
             "[LUMINAIRE] %s" % name.replace("\n", " "), "TILT=NONE",
             "1 -1 1 %d %d 1 2 0 0 0" % (len(vs), len(hs)), "1 1 0",
             " ".join("%g" % v for v in vs), " ".join("%g" % h for h in hs)]
    lines += [" ".join("%.7g" % x for x in row) for row in cd]
    return "\n".join(lines) + "\n"


def fixture_matrix(ph, aim, up=None, roll_deg=0.0):
    """The lamp's rotation in Blender (3 x 3): lumis's R for the file's type and the aim, up
    (Blender directions) and roll, through the frame map."""
    aim_l = blender_to_lumis(aim)
    up_l = blender_to_lumis(up) if up is not None else None
    R = Matrix([list(r) for r in ph.orient(aim_l, up_l, roll_deg)])
    return F_LUMIS_TO_BLENDER @ R


def import_fixture(scene, path, location=(0.0, 0.0, 3.0), aim=(0.0, 0.0, -1.0), up=None,
                   roll_deg=0.0, multiplier=1.0, lumis_path=""):
    """Adds a point lamp for the IES/EULUMDAT file at `location`, aimed along `aim` (Blender
    world), to the collection "lumis fixtures".  Returns a dict: the lamp's name, the file's
    type, flux (lm, times multiplier), the lamp's power (W), the rotation (rows) and the
    peak candela."""
    lumis = import_lumis(lumis_path)
    if not multiplier > 0 or not math.isfinite(multiplier):
        raise LumisError("multiplier: %r is not a positive number" % (multiplier,))
    try:
        ph = lumis.read_photometric(path)
    except lumis.Error as e:
        raise LumisError("%s: %s" % (path, e.message)) from e
    with ph:
        flux = ph.flux
        if not flux > 0:
            raise LumisError("%s: the table's flux is %g lm: nothing to light with" % (path, flux))
        info = ph.info()
        try:
            M = fixture_matrix(ph, aim, up, roll_deg)
        except lumis.Error as e:
            raise LumisError("%s: aim %s, up %s, roll %g: %s" % (
                path, tuple(aim), up, roll_deg, e.message)) from e
        name = os.path.basename(path)
        text = bpy.data.texts.new(name)
        text.write(fixture_ies_text(ph, ph.luminaire or name))
    data = bpy.data.lights.new("lumis %s" % name, "POINT")
    data.energy = flux * multiplier / LUMENS_PER_WATT
    data.shadow_soft_size = 0.0  # a point, as lumis's fixture without "area"
    data.use_nodes = True
    nt = data.node_tree
    ies = nt.nodes.new("ShaderNodeTexIES")
    ies.mode = "INTERNAL"
    ies.ies = text
    emission = next(n for n in nt.nodes if n.type == "EMISSION")
    nt.links.new(ies.outputs["Fac"], emission.inputs["Strength"])
    obj = bpy.data.objects.new(data.name, data)
    m = M.to_4x4()
    m.translation = Vector(location)
    obj.matrix_world = m
    obj["lumis_file"] = os.path.abspath(path)
    obj["lumis_type"] = info["type"]
    obj["lumis_flux_lm"] = flux * multiplier
    obj["lumis_lm_per_w"] = LUMENS_PER_WATT
    coll = bpy.data.collections.get(FIXTURES) or bpy.data.collections.new(FIXTURES)
    if coll.name not in scene.collection.children:
        scene.collection.children.link(coll)
    coll.objects.link(obj)
    return {"lamp": obj.name, "type": info["type"], "flux_lm": flux * multiplier,
            "power_w": data.energy, "rotation": [tuple(r) for r in M],
            "max_candela": info["max_candela"] * multiplier, "text": text.name}


# ---- the user interface -----------------------------------------------------------------

_method_items_cache = []


def world_with_hdri(scene, path, rotation_deg=(0.0, 0.0, 0.0), interpolation="Linear",
                    name="lumis hdri"):
    """A world whose Background shows the map at path through a Mapping node (Point) rotated
    by rotation_deg (X, Y, Z), as a user sets one up: what "Lights from World HDRI" reads
    (the headless script's --hdri, and the add-on's test)."""
    world = bpy.data.worlds.new(name)
    world.use_nodes = True
    nt = world.node_tree
    nt.nodes.clear()
    out = nt.nodes.new("ShaderNodeOutputWorld")
    bg = nt.nodes.new("ShaderNodeBackground")
    env = nt.nodes.new("ShaderNodeTexEnvironment")
    env.image = bpy.data.images.load(os.path.abspath(path), check_existing=True)
    env.interpolation = interpolation
    mapping = nt.nodes.new("ShaderNodeMapping")
    mapping.vector_type = "POINT"
    mapping.inputs["Rotation"].default_value = [math.radians(c) for c in rotation_deg]
    coord = nt.nodes.new("ShaderNodeTexCoord")
    nt.links.new(coord.outputs["Generated"], mapping.inputs["Vector"])
    nt.links.new(mapping.outputs["Vector"], env.inputs["Vector"])
    nt.links.new(env.outputs["Color"], bg.inputs["Color"])
    nt.links.new(bg.outputs["Background"], out.inputs["Surface"])
    scene.world = world
    return world


def _method_items(self, context):
    if not _method_items_cache:
        try:
            names = import_lumis(_prefs_path(context)).light_methods()
        except Exception:  # noqa: BLE001 - the operator reports the import error itself
            names = list(_FALLBACK_METHODS)
        _method_items_cache.extend((n, n, "lumis light-set method %s" % n) for n in names)
    return _method_items_cache


def _prefs_path(context):
    addon = context.preferences.addons.get(__name__) if context else None
    return addon.preferences.lumis_path if addon else ""


class LumisLightsPreferences(bpy.types.AddonPreferences):
    bl_idname = __name__
    lumis_path: StringProperty(
        name="lumis package folder", subtype="DIR_PATH", default="",
        description="The folder holding the lumis Python package (lumis/), when Blender's "
                    "Python cannot import it already (e.g. the source tree's python/)")

    def draw(self, context):
        self.layout.prop(self, "lumis_path")


class LUMIS_OT_lights_from_world(bpy.types.Operator):
    """Sun lamps from the world's HDRI: a lumis light set, lined up with the HDRI as Blender
    shows it, strengths in W/m^2"""
    bl_idname = "lumis.lights_from_world"
    bl_label = "Lights from World HDRI"
    bl_options = {"REGISTER", "UNDO"}

    method: EnumProperty(name="Method", items=_method_items,
                         description="lumis light-set method (docs/lights.md)")
    count: IntProperty(name="Lights", default=16, min=1, max=4096,
                       description="K, the number of lights (sun lamps)")
    params: StringProperty(name="Parameters", default="",
                           description="The method's parameters, NAME=VALUE,... as "
                                       "`lumis lights --param`")
    remove_hdri: BoolProperty(name="Remove HDRI", default=False,
                              description="Unlink the Environment Texture from the world's "
                                          "Background, so that only the lamps light the scene")
    replace: BoolProperty(name="Replace", default=True,
                          description="Remove the lamps of the collection 'lumis lights' first")

    def execute(self, context):
        try:
            r = lights_from_world(context.scene, self.method, self.count, self.params,
                                  self.remove_hdri, self.replace, _prefs_path(context))
        except LumisError as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        self.report({"INFO"}, "lumis: %d sun lamps by %s from %s (irradiance up: lights %.4g, "
                    "map %.4g)" % (r["count"], r["method"], r["source"],
                                   r["irradiance_up"]["lights"], r["irradiance_up"]["map"]))
        return {"FINISHED"}


class LUMIS_OT_import_fixture(bpy.types.Operator):
    """A point lamp from an IES or EULUMDAT file: lumis's photometric model in Cycles' IES
    Texture, power the flux at 683 lm/W, aimed by lumis's rule for the file's type"""
    bl_idname = "lumis.import_fixture"
    bl_label = "Photometric Fixture (IES/EULUMDAT)"
    bl_options = {"REGISTER", "UNDO"}

    filepath: StringProperty(subtype="FILE_PATH")
    filter_glob: StringProperty(default="*.ies;*.IES;*.ldt;*.LDT", options={"HIDDEN"})
    aim: FloatVectorProperty(name="Aim", default=(0.0, 0.0, -1.0), subtype="DIRECTION",
                             description="Where the fixture points (photometric zero for "
                                         "type C, the centre for A and B)")
    roll: FloatProperty(name="Roll", default=0.0, subtype="ANGLE",
                        description="A turn about the aim (C0 towards C90)")
    multiplier: FloatProperty(name="Multiplier", default=1.0, min=1e-6,
                              description="Scales the file's candela (and the lamp's power)")

    def invoke(self, context, event):
        context.window_manager.fileselect_add(self)
        return {"RUNNING_MODAL"}

    def execute(self, context):
        try:
            r = import_fixture(context.scene, self.filepath,
                               tuple(context.scene.cursor.location), tuple(self.aim), None,
                               math.degrees(self.roll), self.multiplier, _prefs_path(context))
        except LumisError as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        self.report({"INFO"}, "lumis: %s, type %s, %.4g lm, %.4g W at %g lm/W" % (
            r["lamp"], r["type"], r["flux_lm"], r["power_w"], LUMENS_PER_WATT))
        return {"FINISHED"}


class WORLD_PT_lumis_lights(bpy.types.Panel):
    bl_label = "lumis lights"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "world"

    def draw(self, context):
        self.layout.operator(LUMIS_OT_lights_from_world.bl_idname, icon="LIGHT_SUN")


def _menu(self, context):
    self.layout.operator(LUMIS_OT_lights_from_world.bl_idname, icon="LIGHT_SUN")
    self.layout.operator(LUMIS_OT_import_fixture.bl_idname, icon="LIGHT_POINT")


def _import_menu(self, context):
    self.layout.operator(LUMIS_OT_import_fixture.bl_idname, text="Photometric Fixture (.ies/.ldt)")


_CLASSES = (LumisLightsPreferences, LUMIS_OT_lights_from_world, LUMIS_OT_import_fixture,
            WORLD_PT_lumis_lights)


def register():
    for c in _CLASSES:
        bpy.utils.register_class(c)
    bpy.types.VIEW3D_MT_light_add.append(_menu)
    bpy.types.TOPBAR_MT_file_import.append(_import_menu)


def unregister():
    bpy.types.TOPBAR_MT_file_import.remove(_import_menu)
    bpy.types.VIEW3D_MT_light_add.remove(_menu)
    for c in reversed(_CLASSES):
        bpy.utils.unregister_class(c)


__all__ = ["lights_from_world", "import_fixture", "fixture_ies_text", "fixture_matrix",
           "LUMENS_PER_WATT", "import_lumis", "lumis_to_blender", "blender_to_lumis",
           "mapping_matrix", "find_environment", "LumisError"]
