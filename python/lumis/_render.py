"""lumis.render: one call of lumis_render_session (liblumis-render.so), as `lumis render` makes
it between loading and writing (docs/python.md, "Rendering")."""

import os

from ._api import Map, _image_to_array
from ._lib import Sink, cstr, ffi, invalid, lib, pystr, render_missing, renderlib

_ESTIMATORS = {"mis": 0, "light": 1, "bsdf": 2}
_KINDS = {"env": 0, "light-set": 1, "luminaires": 2, "photometric": 3}
_K_LIMITS = {0: "none", 1: "fewer-spp", 2: "below-floor", 3: "over-budget"}
_LUM_RESTRICTED = 1  # the tool's default strategy for luminaires (LUMIS_LUM_RESTRICTED)
_TIMED_SPP = 4  # the tool's TOOL_LIGHTS_TIMED_SPP


def scenes():
    """The built-in scenes' names."""
    _need()
    names, p = [], renderlib.lumis_scene_builtin_names()
    while p[len(names)] != ffi.NULL:
        names.append(pystr(p[len(names)]))
    return names


def _need():
    if renderlib is None:
        raise ImportError("lumis.render needs liblumis-render.so.0 beside liblumis.so.0 (built by "
                          "`make run` or `make install`): %s" % render_missing)


def _scene_file(scene, sink, skip_env):
    out = ffi.new("lumis_scene_file **")
    if scene in scenes():
        sink.check(renderlib.lumis_scene_builtin(cstr(scene), sink.c, out), "scene %s" % scene)
    elif os.path.exists(scene) or scene.endswith(".json"):
        opts = ffi.new("lumis_scene_read_options *", {"skip_env_map": int(skip_env),
                                                       "errors": sink.value})
        sink.check(renderlib.lumis_scene_file_read(cstr(scene), opts, out), scene)
    else:
        raise invalid("scene: '%s' is neither a built-in scene (%s) nor a scene file" % (
            scene, ", ".join(scenes())))
    return out[0]


def _envmap_from_image(img, rotation_deg, scale, sink, source):
    desc = ffi.new("lumis_envmap_desc *", {"pixels": img.pixels, "width": img.width,
                                           "height": img.height, "rotation_deg": rotation_deg,
                                           "scale": scale, "errors": sink.value})
    out = ffi.new("lumis_envmap **")
    sink.check(lib.lumis_envmap_create(desc, out), source)
    return out[0]


def render(scene="spheres", env=None, method=None, estimator="mis", lights=None, lights_k=0,
           lights_mode="point", lights_params=None, interleave=0, upsample=0, spp=0,
           time_budget=0.0, seed=1, sequence=None, size=None, threads=0, bounces=0,
           light_samples=0, bsdf_samples=0, power_heuristic=False, hide_environment=False,
           rotation_deg=0.0, scale=1.0, lights_draws=0):
    """Renders a scene as `lumis render` does with the same settings, bit for bit for the same
    seed.  Returns (image H x W x 3 float32, row 0 the top; a dict of what the render chose and
    what it cost).

    scene: a built-in name (lumis.scenes()) or a scene file.  A scene that places luminaires
    or photometric fixtures is lit by them; otherwise by env (a map file or spec, or a
    lumis.Map; None: the scene file's map, else "sky") with rotation_deg and scale, through
    the sampler `method` (None: the library's default) and `estimator` ("mis", "light",
    "bsdf": no sampler), or, with `lights` (a light-set method), by lights_k lights in
    lights_mode ("point", "stratified") with lights_params (a dict or "NAME=VALUE,...");
    lights_draws N > 0 (stratified): N draws per vertex over regions chosen per shading point,
    as --lights-draws.
    spp samples per pixel (0: 16), or time_budget seconds of wall time (the light set's
    making included).  seed and sequence ("sobol", "halton", "pcg", ...: where the numbers come from),
    size (W, H) instead of the scene camera's, threads (0: every core), bounces (path
    tracing), light_samples, bsdf_samples, power_heuristic, hide_environment as the tool's
    options.  Refusals raise lumis.Error with the library's message."""
    _need()
    if estimator not in _ESTIMATORS:
        raise invalid("estimator: unknown '%s' (one of %s)" % (estimator, ", ".join(_ESTIMATORS)))
    keep = []  # cdata the C structs point into, alive until the render returns
    sink = Sink()
    file = scene_ = envp = smp = None
    own_env = False
    light_set = ffi.NULL
    try:
        file = _scene_file(scene, sink, skip_env=env is not None)
        lum = file.luminaire_count > 0
        fixtures = not lum and file.photometric_count > 0
        self_lit = lum or fixtures
        if not lum and file.luminaires_listed > 0:
            raise invalid("%s: every luminaire of the scene has intensity 0: nothing lights it"
                          % scene)
        # the map, unless the scene lights itself (a map or sampler asked for regardless is
        # given, for the session's check to refuse by name, as the tool does)
        if isinstance(env, Map):
            envp = env.ptr
        elif env is not None or not self_lit or method is not None:
            spec = env
            if spec is None:
                if file.env_image != ffi.NULL:
                    envp = _envmap_from_image(file.env_image, file.env_rotation_deg,
                                              file.env_scale, sink, pystr(file.env_map))
                    own_env = True
                spec = None if own_env else (pystr(file.env_map) or "sky")
            if spec is not None:
                m = Map.read(spec, rotation_deg, scale)
                keep.append(m)
                envp = m.ptr
        if envp is not None and ((not self_lit and lights is None and estimator != "bsdf")
                                 or method is not None):
            mm = ffi.new("lumis_sampler_method *")
            if method is not None and lib.lumis_sampler_method_from_name(cstr(method), mm) != 0:
                raise invalid("method: unknown sampler method '%s'" % method)
            sd = ffi.new("lumis_sampler_desc *", {"method": mm[0], "errors": sink.value})
            out = ffi.new("lumis_sampler **")
            sink.check(lib.lumis_sampler_create(envp, sd, out), "sampler")
            smp = out[0]
        cam = ffi.new("lumis_camera *", file.camera)
        if size is not None:
            w, h = size
            if int(w) < 1 or int(h) < 1:
                raise invalid("size: expected (width, height) >= 1, got %s" % (tuple(size),))
            cam.width, cam.height = int(w), int(h)
        sq = ffi.new("lumis_sequence *")
        if sequence is not None and lib.lumis_sequence_from_name(cstr(sequence), sq) != 0:
            raise invalid("sequence: unknown '%s'" % sequence)
        mode = ffi.new("lumis_lights_mode *")
        if renderlib.lumis_lights_mode_from_name(cstr(lights_mode), mode) != 0:
            raise invalid("lights_mode: unknown '%s' (point or stratified)" % lights_mode)
        sout = ffi.new("lumis_scene **")
        sink.check(renderlib.lumis_scene_create(file.objects, file.object_count, sink.c, sout),
                   "scene")
        scene_ = sout[0]

        sess = ffi.new("lumis_session_desc *")
        rd = sess.render
        rd.camera = cam
        kind = "luminaires" if lum else "photometric" if fixtures else \
            "light-set" if lights is not None else "env"
        rd.lighting.kind = _KINDS[kind]
        rd.lighting.env = envp if envp is not None else ffi.NULL
        rd.lighting.sampler = smp if smp is not None else ffi.NULL
        rd.lighting.estimator = _ESTIMATORS[estimator]
        rd.lighting.hide_environment = int(bool(hide_environment))
        rd.lighting.light_set.mode = mode[0]
        rd.lighting.light_set.draws = int(lights_draws)
        if lum:
            ll = ffi.new("lumis_luminaire_lighting *", {"instances": file.luminaires,
                                                         "count": file.luminaire_count,
                                                         "strategy": _LUM_RESTRICTED})
            keep.append(ll)
            rd.lighting.luminaires = ll
        if fixtures:
            pl = ffi.new("lumis_photometric_lighting *", {"instances": file.photometrics,
                                                           "count": file.photometric_count})
            keep.append(pl)
            rd.lighting.photometric = pl
        rd.power_heuristic = int(bool(power_heuristic))
        rd.spp = spp
        rd.light_samples = light_samples
        rd.bsdf_samples = bsdf_samples
        rd.seed = seed
        rd.sequence = sq[0]
        rd.threads = threads
        rd.max_bounces = bounces
        rd.errors = sink.value
        if lights is not None:
            name = ffi.new("char[]", cstr(lights))
            keep.append(name)
            sess.lights = name
            if lights_params is not None:
                from ._api import _params_text  # noqa: PLC0415
                p = ffi.new("lumis_light_params *")
                sink.check(lib.lumis_light_params_parse(p, cstr(_params_text(lights_params)),
                                                        sink.c), "lights_params")
                keep.append(p)
                sess.lights_params = p
        sess.lights_k = lights_k
        sess.interleave = interleave
        sess.upsample = upsample
        sess.time_budget = time_budget
        sess.spent = lib.lumis_sampler_build_ms(smp) / 1000.0 if smp is not None else 0.0
        sess.timed_spp = _TIMED_SPP
        sink.check(renderlib.lumis_session_check(sess), "render")
        img = ffi.new("lumis_image **")
        r = ffi.new("lumis_session_result *")
        sink.check(renderlib.lumis_render_session(scene_, sess, img, r), "render")
        light_set = r.light_set
        try:
            image = _image_to_array(img[0])
        finally:
            lib.lumis_image_destroy(img[0])
        st = r.stats
        result = {
            "scene": scene, "lighting": kind, "width": cam.width, "height": cam.height,
            "sampler": pystr(lib.lumis_sampler_method_name(lib.lumis_sampler_get_method(smp)))
            if smp is not None else None,
            "estimator": estimator, "lights": lights, "lights_k": r.lights_k,
            "lights_mode": lights_mode if lights is not None else None,
            "lights_draws": int(lights_draws) if lights is not None else None,
            "upsample": r.upsample, "seed": seed, "sequence": sequence or "sobol",
            "spp": st.spp, "passes": st.passes, "threads": st.threads,
            "seconds": st.seconds, "camera_rays": st.camera_rays, "shadow_rays": st.shadow_rays,
            "bounce_rays": st.bounce_rays, "light_samples": st.light_samples,
            "prep_seconds": r.prep_seconds, "budget_used_seconds": r.budget_used_seconds,
            "time_budget": time_budget, "lights_build_ms": r.lights_build_ms,
            "pilot_count": r.pilot_count, "pilot_k": list(r.pilot_k)[:r.pilot_count],
            "k_limit": _K_LIMITS.get(r.k_limit, str(r.k_limit)), "spp_planned": r.spp_planned,
            "wall_seconds": r.wall_seconds, "cpu_seconds": r.cpu_seconds,
            "cpu_share": r.cpu_share, "threads_busy": r.threads_busy,
        }
        return image, result
    finally:
        if light_set != ffi.NULL:
            lib.lumis_light_set_destroy(light_set)
        if scene_ is not None:
            renderlib.lumis_scene_destroy(scene_)
        if smp is not None:
            lib.lumis_sampler_destroy(smp)
        if own_env:
            lib.lumis_envmap_destroy(envp)
        for m in keep:
            if isinstance(m, Map):
                m.close()
        if file is not None:
            renderlib.lumis_scene_file_destroy(file)


_PHOTOMETRIC_TYPES = {"C": 1, "B": 2, "A": 3}


def photometric_orient(type, aim, up=None, roll_deg=0.0):  # noqa: A002 - the C argument's name
    """lumis_photometric_orient: the rotation R (3 x 3 float64, world = R local; local -z the
    aim) of a fixture of photometric type "C", "B" or "A" aimed along `aim` (lumis's world, y
    up), local +x from `up` or the type's default, then rolled roll_deg about the aim
    (docs/photometric.md, "Aiming a fixture")."""
    _need()
    import numpy as np  # noqa: PLC0415
    if type not in _PHOTOMETRIC_TYPES:
        raise invalid("type: '%s' is not a photometric type (C, B, A)" % (type,))
    a = [float(x) for x in aim]
    if len(a) != 3:
        raise invalid("aim: 3 components expected, got %d" % len(a))
    u = ffi.NULL
    if up is not None:
        uu = [float(x) for x in up]
        if len(uu) != 3:
            raise invalid("up: 3 components expected, got %d" % len(uu))
        u = ffi.new("lumis_vec3 *", uu)
    R = ffi.new("double[9]")
    st = renderlib.lumis_photometric_orient(_PHOTOMETRIC_TYPES[type], a, u, float(roll_deg), R)
    if st != lib.LUMIS_OK:
        raise invalid("photometric_orient: aim %s, up %s, roll %g refused (a zero or non-finite "
                      "aim or roll, or an up along the aim)" % (a, up, float(roll_deg)))
    return np.array(list(R), dtype=np.float64).reshape(3, 3)
