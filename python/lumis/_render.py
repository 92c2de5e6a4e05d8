"""lumis.render: one call of lumis_render_session (liblumis-render.so), as `lumis render` makes
it between loading and writing (docs/python.md, "Rendering")."""

import math
import os

import numpy as np

from ._api import Map, Photometric, _image_to_array
from ._lib import Sink, cstr, ffi, invalid, iolib, lib, pystr, render_missing, renderlib

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


def _scene_file(scene, sink, skip_env, luminaire=None):
    out = ffi.new("lumis_scene_file **")
    if scene in scenes():
        if luminaire is not None:  # placed instead of the scene's own, which is not acquired
            sink.check(renderlib.lumis_scene_builtin_with_luminaire(cstr(scene), luminaire,
                                                                    sink.c, out),
                       "scene %s" % scene)
        else:
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


class Fixture:
    """A photometric fixture placed by options, as `lumis render --fixture PATH` places one:
    at (where it is), aim (a point it aims at; None: straight down, -y), up (where its local
    +x points, made perpendicular to the aim; None: the type's default), roll_deg (turned
    about its aim), multiplier (its candela times it, > 0; LM-63's lamp-tilt factor at the
    aim applies on top, as the tool's) and area (its luminous opening, not a point).  A dict
    with these keys is taken as one."""

    def __init__(self, path, at, aim=None, up=None, roll_deg=0.0, multiplier=1.0, area=False):
        self.path, self.at, self.aim, self.up = path, at, aim, up
        self.roll_deg, self.multiplier, self.area = roll_deg, multiplier, area

    def __repr__(self):
        return "Fixture(%r, at=%r, aim=%r, up=%r, roll_deg=%r, multiplier=%r, area=%r)" % (
            self.path, self.at, self.aim, self.up, self.roll_deg, self.multiplier, self.area)


def _triple(v, what):
    try:
        t = [float(x) for x in v]
    except (TypeError, ValueError):
        t = []
    if len(t) != 3 or not all(math.isfinite(x) for x in t):
        raise invalid("%s: expected X, Y, Z (three finite numbers), got %r" % (what, v))
    return t


def _place_fixtures(fixtures, keep, files):
    """The fixtures as lumis_photometric_instance values (the tool's load_fixture, one per
    fixture): files gets each Photometric (closed by the caller after the render)."""
    fixtures = list(fixtures)
    arr = ffi.new("lumis_photometric_instance[]", max(len(fixtures), 1))
    keep.append(arr)
    for i, fx in enumerate(fixtures):
        if isinstance(fx, dict):
            try:
                fx = Fixture(**fx)
            except TypeError as e:
                raise invalid("fixtures[%d]: %s (keys: path, at, aim, up, roll_deg, multiplier, "
                              "area)" % (i, e)) from None
        at = _triple(fx.at, "fixtures[%d].at" % i)
        target = _triple(fx.aim, "fixtures[%d].aim" % i) if fx.aim is not None else None
        m = float(fx.multiplier)
        if not (0 < m <= 1e30):
            raise invalid("fixtures[%d].multiplier: %r (expected a number > 0)" % (i, fx.multiplier))
        roll = float(fx.roll_deg)
        if not (abs(roll) <= 36000):
            raise invalid("fixtures[%d].roll_deg: %r (expected degrees)" % (i, fx.roll_deg))
        f = Photometric(fx.path)
        files.append(f)
        aimp = ffi.new("lumis_vec3 *", [target[a] - at[a] for a in range(3)] if target
                       else [0.0, -1.0, 0.0])
        aim = aimp[0]  # aimp owns it: alive to the end of the iteration
        info = ffi.new("lumis_photometric_info *")
        lib.lumis_photometric_get_info(f.ptr.model, info)
        inst = arr[i]
        if renderlib.lumis_photometric_orient(info.type, aim, ffi.NULL, roll,
                                              inst.placement.r) != lib.LUMIS_OK:
            raise invalid("fixtures[%d].aim: a point other than its position (at)" % i)
        if fx.up is not None:
            up = ffi.new("lumis_vec3 *", _triple(fx.up, "fixtures[%d].up" % i))
            if renderlib.lumis_photometric_orient(info.type, aim, up, roll,
                                                  inst.placement.r) != lib.LUMIS_OK:
                raise invalid("fixtures[%d].up: a direction not along the aim (the fixture's "
                              "local +x is made perpendicular to the aim)" % i)
        for a in range(3):
            inst.placement.t[a] = at[a]
        inst.photometric = f.ptr.model
        inst.multiplier = m * iolib.lumis_photometric_tilt_factor(f.ptr, info.type, aim)
        inst.area = int(bool(fx.area))
    return arr, len(fixtures)


def _load_luminaire(spec, sink):
    """A light-field luminaire: "preset:car|bike|small" (acquired from its emitter: seconds;
    the tool keeps them in a cache, this does not) or a manifest (lumis luminaire create)."""
    out = ffi.new("lumis_luminaire **")
    if spec.startswith("preset:"):
        pr = ffi.new("lumis_luminaire_preset *")
        if lib.lumis_luminaire_preset_from_name(cstr(spec[7:]), pr) != lib.LUMIS_OK:
            raise invalid("luminaire: %s: unknown preset (preset:car, preset:bike or "
                          "preset:small)" % spec)
        sink.check(lib.lumis_luminaire_preset_create(pr[0], 0, sink.c, out), spec)
    else:
        ro = ffi.new("lumis_luminaire_read_options *", {"errors": sink.value})
        sink.check(iolib.lumis_luminaire_read(cstr(spec), ro, out), spec)
    return out[0]


def render_sequence(name, samples, seed=1, spp=0, width=1, pixel=(0, 0), dimension=0,
                    per_sample=1, first_sample=0):
    """The 2D points a render draws (lumis_sequence_fill): camera samples first_sample ..
    first_sample + samples - 1 of pixel (x, y) of an image `width` wide, in one dimension of
    the render's sequence (0: the camera's jitter; docs/sampling.md has the layout),
    per_sample points each, as a (samples x per_sample) x 2 float64 array: the numbers
    `lumis render --sequence NAME --seed SEED --spp SPP` takes there.  name: any sequence
    ("default" is sobol); spp: the render's spp, which stratified and zsobol plan for (0:
    2^16, as the library's)."""
    _need()
    sink = Sink()
    q = ffi.new("lumis_sequence *")
    sink.check(renderlib.lumis_sequence_from_name(cstr(name), q), "sequence '%s'" % name)
    x, y = pixel
    n = int(samples) * max(int(per_sample), 1) if int(samples) >= 0 else 0
    out = np.empty((n, 2), dtype=np.float64)
    d = ffi.new("lumis_sequence_desc *", {
        "sequence": q[0], "seed": int(seed), "planned_spp": int(spp), "width": int(width),
        "x": int(x), "y": int(y), "dimension": int(dimension), "per_sample": int(per_sample),
        "errors": sink.value})
    sink.check(renderlib.lumis_sequence_fill(d, int(first_sample), int(samples),
                                             ffi.cast("double *", ffi.from_buffer(out)) if n
                                             else ffi.NULL), "sequence '%s'" % name)
    return out


def _auto_result(r):
    """The automatic estimator's choice and pilots, as the sidecar's auto_estimator."""
    def name(k):
        return pystr(renderlib.lumis_auto_candidate_name(k))
    cands = []
    for k in range(r.auto_count):
        c = r.auto_candidates[k]
        cands.append({"name": name(k), "lights_k": c.lights_k, "sun": bool(c.sun),
                      "measured": c.pilot_spp > 0, "pilot_spp": c.pilot_spp,
                      "relmse_at_1spp": c.error_per_spp if c.pilot_spp else None,
                      "relmse_at_1spp_se": c.error_se if c.pilot_spp else None,
                      "seconds_per_spp": c.per_spp if c.pilot_spp else None,
                      "relmse_x_seconds": c.efficiency if c.pilot_spp else None,
                      "seconds_before": c.once})
    predict = r.auto_mode == 1  # LUMIS_AUTO_PREDICT (2: LUMIS_AUTO_PILOTS)
    return {"chosen": name(r.auto_chosen), "mode": "predict" if predict else "pilots",
            "diffuse_share": r.auto_diffuse_share if predict else None,
            "rays_met": r.auto_rays if predict else None,
            "prior": r.auto_prior, "held": bool(r.auto_held),
            "seconds": r.auto_seconds,
            "pilot_seconds": r.auto_pilot_seconds, "pilot_cpu_seconds": r.auto_pilot_cpu,
            "pilot_cap_seconds": r.auto_cap or None,
            "sun_share": r.auto_sun.share if r.auto_sun.found else None, "candidates": cands}


def render(scene="spheres", env=None, method=None, estimator=None, lights=None, lights_k=0,
           lights_mode="point", lights_params=None, interleave=0, upsample=0, spp=0,
           time_budget=0.0, seed=1, sequence=None, size=None, threads=0, bounces=0,
           light_samples=0, bsdf_samples=0, power_heuristic=False, hide_environment=False,
           rotation_deg=0.0, scale=1.0, fixtures=None, luminaire=None, lights_draws=0,
           auto=None):
    """Renders a scene as `lumis render` does with the same settings, bit for bit for the same
    seed.  Returns (image H x W x 3 float32, row 0 the top; a dict of what the render chose and
    what it cost).

    scene: a built-in name (lumis.scenes()) or a scene file.  A scene that places luminaires
    or photometric fixtures is lit by them; otherwise by env (a map file or spec, or a
    lumis.Map; None: the scene file's map, else "sky") with rotation_deg and scale, through
    the sampler `method` (None: the library's default) and `estimator` ("mis", "light",
    "bsdf": no sampler; None: "mis"), or, with `lights` (a light-set method), by lights_k lights in
    lights_mode ("point", "stratified") with lights_params (a dict or "NAME=VALUE,...");
    lights_draws N > 0 (stratified): N draws per vertex over regions chosen per shading point,
    as --lights-draws.
    spp samples per pixel (0: 16), or time_budget seconds of wall time (the light set's
    making included).  seed and sequence ("sobol", "halton", "pcg", ...: where the numbers come from),
    size (W, H) instead of the scene camera's, threads (0: every core), bounces (path
    tracing), light_samples, bsdf_samples, power_heuristic, hide_environment as the tool's
    options.  fixtures: a list of lumis.Fixture (or dicts of its fields) lighting the scene
    instead of its own fixtures, as `--fixture FILE --fixture-at ...` places one; luminaire:
    a manifest or "preset:NAME" replacing every luminaire the scene places, as
    `--luminaire`.
    auto: the automatic estimator (docs/render.md), as `lumis render`: None (the default)
    uses it when the map lights the scene and no argument fixes the estimator (method,
    estimator, lights and its options, light_samples, bsdf_samples, power_heuristic); True
    asks for it (method then chooses the MIS candidate's sampler), "pilots" is
    --auto-pilots (chosen by pilot renders instead of the prediction), False is --no-auto.  The
    result's "auto" says what it chose and why (None: not used).
    Refusals raise lumis.Error with the library's message."""
    _need()
    fixed = (method is not None or estimator is not None or lights is not None or lights_k
             or lights_params is not None or interleave or upsample or lights_draws
             or light_samples or bsdf_samples or power_heuristic or lights_mode != "point")
    if auto not in (None, True, False, "pilots"):
        raise invalid("auto: None, True, False or 'pilots', not %r" % (auto,))
    estimator = "mis" if estimator is None else estimator
    if estimator not in _ESTIMATORS:
        raise invalid("estimator: unknown '%s' (one of %s)" % (estimator, ", ".join(_ESTIMATORS)))
    keep = []  # cdata the C structs point into, alive until the render returns
    sink = Sink()
    file = scene_ = envp = smp = None
    own_env = False
    light_set = ffi.NULL
    repl = None  # luminaire=: destroyed after the scene file that borrows it
    pfiles = []  # fixtures=: their photometric files
    given = fixtures
    try:
        if luminaire is not None:
            repl = _load_luminaire(luminaire, sink)
        file = _scene_file(scene, sink, skip_env=env is not None, luminaire=repl)
        lum = file.luminaire_count > 0
        if repl is not None and not lum:
            raise invalid("luminaire %s: the scene places no luminaire (try the scene "
                          "'headlight')" % luminaire)
        for k in range(file.luminaire_count if repl is not None else 0):
            file.luminaires[k].luminaire = repl
        fixtures = not lum and (file.photometric_count > 0 or given is not None)
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
        if fixtures or given is not None:
            inst, count = (_place_fixtures(given, keep, pfiles) if given is not None
                           else (file.photometrics, file.photometric_count))
            pl = ffi.new("lumis_photometric_lighting *", {"instances": inst, "count": count})
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
        sess.auto_estimator = (2 if auto == "pilots" else
                               1 if auto is True or (auto is None and not fixed and kind == "env"
                                                     and smp is not None) else 0)
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
            "auto": _auto_result(r) if r.auto_count > 0 else None,
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
        for f in pfiles:
            f.close()
        if file is not None:
            renderlib.lumis_scene_file_destroy(file)
        if repl is not None:
            lib.lumis_luminaire_destroy(repl)


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
