"""The bindings: maps, samplers, light sets, photometric files, sequences and metrics."""

import numpy as np

from ._lib import (Handle, Sink, check, cstr, ffi, float_array, image_array, image_struct, invalid,
                   iolib, lib, pystr)

# ---- images and maps -----------------------------------------------------------------------

_FORMATS = {0: None, 1: "exr", 2: "hdr", 3: "pfm", 4: "png"}


def _dptr(a):
    """A C-contiguous float64 array as double * (borrowed: keep a alive across the call)."""
    return ffi.cast("double *", ffi.from_buffer(a))


def _vptr(a):
    """A C-contiguous N x 3 float32 array as lumis_vec3 * (borrowed, as _dptr)."""
    return ffi.cast("lumis_vec3 *", ffi.from_buffer(a))


def _replaced_dict(r):
    return {"nan": int(r.nan), "inf": int(r.inf), "negative": int(r.negative),
            "negative_min": float(r.negative_min), "negative_sum": float(r.negative_sum)}


def _image_to_array(img):
    n = img.width * img.height * 3
    a = np.frombuffer(ffi.buffer(img.pixels, n * 4), dtype=np.float32).copy()
    return a.reshape(img.height, img.width, 3)


def _read(fn, spec, max_pixels, threads):
    sink = Sink()
    opts = ffi.new("lumis_read_options *", {"max_pixels": max_pixels, "threads": threads,
                                            "errors": sink.value})
    out = ffi.new("lumis_image **")
    info = ffi.new("lumis_read_info *")
    sink.check(fn(cstr(spec), opts, out, info), spec)
    try:
        arr = _image_to_array(out[0])
    finally:
        lib.lumis_image_destroy(out[0])
    meta = {"format": _FORMATS.get(int(info.format)), "replaced": _replaced_dict(info.replaced),
            "had_alpha": bool(info.had_alpha), "grey": bool(info.grey)}
    return arr, meta


def read_image(path, max_pixels=0, threads=0):
    """An image file (EXR, HDR, PFM; format from the content) as an H x W x 3 float32 array,
    row 0 the image's top.  Non-finite and negative values come back as 0."""
    return _read(iolib.lumis_image_read, path, max_pixels, threads)[0]


def write_image(path, pixels, exr_half=False, compression="zip", exposure_ev=0.0,
                tonemap="clamp"):
    """Writes an H x W x 3 array (row 0 the top) as EXR, HDR, PFM or PNG (from the extension),
    through a temporary file renamed on success."""
    a = image_array(pixels, "pixels")
    sink = Sink()
    comp = ffi.new("lumis_exr_compression *")
    check(iolib.lumis_exr_compression_from_name(cstr(compression), comp),
          "compression '%s'" % compression)
    tm = ffi.new("lumis_tonemap *")
    check(iolib.lumis_tonemap_from_name(cstr(tonemap), tm), "tonemap '%s'" % tonemap)
    opts = ffi.new("lumis_write_options *", {"exr_half": int(bool(exr_half)),
                                             "exr_compression": comp[0], "exposure_ev": exposure_ev,
                                             "tonemap": tm[0], "errors": sink.value})
    sink.check(iolib.lumis_image_write(cstr(path), image_struct(a), opts), path)


class Map(Handle):
    """An equirectangular environment map (lumis_envmap): y up, row 0 the zenith, column u
    at azimuth 2 pi u from +x towards +z (docs/coordinates.md)."""

    def __init__(self, pixels, rotation_deg=0.0, scale=1.0, max_pixels=0, source=None,
                 read_info=None):
        """From an H x W x 3 float array (row 0 the zenith); copied.  Non-finite and negative
        values become 0 and are counted (.replaced)."""
        a = image_array(pixels, "pixels")
        sink = Sink()
        desc = ffi.new("lumis_envmap_desc *", {
            "pixels": ffi.cast("float *", ffi.from_buffer(a)), "width": a.shape[1],
            "height": a.shape[0], "rotation_deg": rotation_deg,
            "scale": 0.0 if scale == 1.0 else scale, "max_pixels": max_pixels,
            "errors": sink.value})
        out = ffi.new("lumis_envmap **")
        sink.check(lib.lumis_envmap_create(desc, out), source or "map")
        super().__init__(out[0], lib.lumis_envmap_destroy)
        self.source = source
        self.read_info = read_info

    @classmethod
    def read(cls, spec, rotation_deg=0.0, scale=1.0, max_pixels=0, threads=0):
        """A map file (.exr, .hdr, .pfm) or a procedural spec "sky[:WxH]" / "studio[:WxH]",
        as the tool's MAP arguments (lumis_map_read)."""
        arr, meta = _read(iolib.lumis_map_read, spec, max_pixels, threads)
        return cls(arr, rotation_deg, scale, max_pixels, source=spec, read_info=meta)

    width = property(lambda self: lib.lumis_envmap_width(self.ptr))
    height = property(lambda self: lib.lumis_envmap_height(self.ptr))
    shape = property(lambda self: (self.height, self.width, 3))
    rotation_deg = property(lambda self: lib.lumis_envmap_rotation_deg(self.ptr))
    scale = property(lambda self: lib.lumis_envmap_scale(self.ptr))

    @property
    def replaced(self):
        """Channel values replaced by 0 (NaN, infinite, negative): by the file's reader
        (Map.read) and when the map was built."""
        r = _replaced_dict(lib.lumis_envmap_replaced(self.ptr))
        if self.read_info:
            f = self.read_info["replaced"]
            for k in ("nan", "inf", "negative", "negative_sum"):
                r[k] += f[k]
            r["negative_min"] = min(r["negative_min"], f["negative_min"])
        return r

    def to_array(self):
        """The sanitized pixels, unscaled and unrotated: a new H x W x 3 float32 array, row 0
        the zenith (the top of the image)."""
        n = self.width * self.height * 3
        a = np.frombuffer(ffi.buffer(lib.lumis_envmap_pixels(self.ptr), n * 4), dtype=np.float32)
        return a.copy().reshape(self.height, self.width, 3)

    def info(self):
        """The statistics of `lumis info` (scale applied): a dict with its JSON's names."""
        st = ffi.new("lumis_envmap_stats *")
        check(lib.lumis_envmap_stats_compute(self.ptr, st), "map statistics")
        return {"width": st.width, "height": st.height, "min_luminance": st.min_luminance,
                "max_luminance": st.max_luminance,
                "min_positive_luminance": st.min_positive_luminance,
                "avg_luminance": st.avg_luminance, "dynamic_range": st.dynamic_range,
                "power": st.power, "power_rgb": list(st.power_rgb), "top1_share": st.top1_share,
                "top01_share": st.top01_share, "black_pixels": int(st.black_pixels)}

    def __repr__(self):
        if self.closed:
            return "<lumis.Map closed>"
        return "<lumis.Map %s %dx%d>" % (self.source or "array", self.width, self.height)


def read_map(spec, rotation_deg=0.0, scale=1.0, max_pixels=0, threads=0):
    """Map.read: a file or a "sky[:WxH]" / "studio[:WxH]" spec."""
    return Map.read(spec, rotation_deg, scale, max_pixels, threads)


# ---- samplers ------------------------------------------------------------------------------

_IMPORTANCE = {"luminance": 1, "average": 2, "max-channel": 3}
_SAMPLE_DTYPE = np.float32  # lumis_env_sample: 7 floats (dir, pdf, radiance)


def sampler_methods():
    """The sampler methods' names."""
    return [pystr(lib.lumis_sampler_method_name(m)) for m in range(1, lib.LUMIS_METHOD_COUNT)]


class Sampler(Handle):
    """A sampler of a map's radiance (lumis_sampler): directions with their density per
    steradian.  Immutable once built; threads may share it (calls release the GIL)."""

    def __init__(self, map, method="inversion-guided", importance="luminance", compensate=False,
                 kdtree_blocks=0, kdtree_uniform_angles=False):
        if not isinstance(map, Map):
            raise invalid("map: expected a lumis.Map, got %s" % type(map).__name__)
        m = ffi.new("lumis_sampler_method *")
        if lib.lumis_sampler_method_from_name(cstr(method), m) != lib.LUMIS_OK:
            raise invalid("method: unknown sampler method '%s' (one of %s)" % (
                method, ", ".join(sampler_methods())))
        if importance not in _IMPORTANCE:
            raise invalid("importance: unknown '%s' (one of %s)" % (importance, ", ".join(_IMPORTANCE)))
        sink = Sink()
        desc = ffi.new("lumis_sampler_desc *", {
            "method": m[0], "importance": _IMPORTANCE[importance], "compensate": int(bool(compensate)),
            "kdtree_blocks": kdtree_blocks, "kdtree_uniform_angles": int(bool(kdtree_uniform_angles)),
            "errors": sink.value})
        out = ffi.new("lumis_sampler **")
        sink.check(lib.lumis_sampler_create(map.ptr, desc, out), "sampler %s" % method)
        super().__init__(out[0], lib.lumis_sampler_destroy)
        self.map = map  # the C sampler holds its own reference; this keeps the Python one

    method = property(lambda self: pystr(lib.lumis_sampler_method_name(
        lib.lumis_sampler_get_method(self.ptr))))
    table_bytes = property(lambda self: lib.lumis_sampler_table_bytes(self.ptr))
    total_bytes = property(lambda self: lib.lumis_sampler_total_bytes(self.ptr))
    build_ms = property(lambda self: lib.lumis_sampler_build_ms(self.ptr))
    uniform_fallback = property(lambda self: bool(lib.lumis_sampler_is_uniform_fallback(self.ptr)))
    kdtree_alpha = property(lambda self: lib.lumis_sampler_kdtree_alpha(self.ptr))
    kdtree_blocks = property(lambda self: lib.lumis_sampler_kdtree_blocks(self.ptr))

    def sample(self, u, radiance=False, out=None):
        """Directions from N pairs of uniform numbers in [0, 1) (u: N x 2 float64; float32 is
        converted): (directions N x 3 float32, pdf N float32 per steradian), and the map's
        radiance N x 3 with radiance=True.  One call of lumis_sampler_sample_n; the arrays
        are strided views of one N x 7 block, as C wrote it (np.ascontiguousarray for a
        packed copy).  out: an N x 7 float32 C-contiguous array to write into instead of a
        new one (what a loop drawing batch after batch reuses: no fresh pages to fault in)."""
        uu = float_array(u, np.float64, (2,), "u")
        n = uu.shape[0]
        if out is None:
            out = np.empty((n, 7), dtype=_SAMPLE_DTYPE)
        elif not (isinstance(out, np.ndarray) and out.dtype == _SAMPLE_DTYPE and out.shape == (n, 7)
                  and out.flags.c_contiguous and out.flags.writeable):
            raise invalid("out: expected a writeable C-contiguous float32 array of shape (%d, 7)" % n)
        if n:
            lib.lumis_sampler_sample_n(self.ptr, ffi.cast("double *", ffi.from_buffer(uu)), n,
                                       ffi.cast("lumis_env_sample *", ffi.from_buffer(out)))
        # views into the samples as C wrote them (7 floats a sample): no copy
        d, p = out[:, 0:3], out[:, 3]
        return (d, p, out[:, 4:7]) if radiance else (d, p)

    def pdf(self, directions, radiance=False):
        """Density per steradian of drawing each of N world directions (N x 3 float32, need
        not be normalized; float64 is converted), and the map's radiance there with
        radiance=True.  One call of lumis_sampler_pdf_n."""
        d = float_array(directions, np.float32, (3,), "directions")
        n = d.shape[0]
        p = np.empty(n, dtype=np.float32)
        rad = np.empty((n, 3), dtype=np.float32) if radiance else None
        if n:
            lib.lumis_sampler_pdf_n(
                self.ptr, ffi.cast("lumis_vec3 *", ffi.from_buffer(d)), n,
                ffi.cast("float *", ffi.from_buffer(p)),
                ffi.cast("lumis_rgb *", ffi.from_buffer(rad)) if radiance else ffi.NULL)
        return (p, rad) if radiance else p

    def invert(self, directions):
        """The (u1, u2) that sample() maps to each direction: N x 2 float64.  Inversion,
        inversion-guided, hierarchical and uniform only (UnsupportedError otherwise); a zero
        or non-finite direction raises InvalidArgumentError naming its index."""
        d = float_array(directions, np.float32, (3,), "directions")
        n = d.shape[0]
        u = np.empty((n, 2), dtype=np.float64)
        failed = ffi.new("size_t *")
        if n:
            st = lib.lumis_sampler_invert_n(self.ptr, ffi.cast("lumis_vec3 *", ffi.from_buffer(d)),
                                            n, ffi.cast("double *", ffi.from_buffer(u)), failed)
            if st != lib.LUMIS_OK:
                check(st, "invert (%s), direction %d %s" % (self.method, failed[0],
                                                            d[failed[0]].tolist()))
        return u

    def __repr__(self):
        return "<lumis.Sampler closed>" if self.closed else "<lumis.Sampler %s>" % self.method


# ---- light sets ----------------------------------------------------------------------------

def light_methods():
    """The light-set methods' names (lumis_lights_method_names)."""
    names, p = [], lib.lumis_lights_method_names()
    while p[len(names)] != ffi.NULL:
        names.append(pystr(p[len(names)]))
    return names


def _light_dtype():
    off = lambda f: ffi.offsetof("lumis_light", f)  # noqa: E731
    return np.dtype({"names": ["direction", "extent", "power", "solid_angle", "pixels", "kind"],
                     "formats": [(np.float32, 3), np.float32, (np.float64, 3), np.float64,
                                 np.int32, np.int32],
                     "offsets": [off("dir"), off("extent"), off("power"), off("solid_angle"),
                                 off("pixels"), off("kind")],
                     "itemsize": ffi.sizeof("lumis_light")})


LIGHT_DTYPE = _light_dtype()
LIGHT_KINDS = {0: "region", 1: "env-direct", 2: "env-indirect"}


def _params_text(params):
    if params is None:
        return ""
    if isinstance(params, str):
        return params
    if isinstance(params, dict):
        return ",".join("%s=%s" % (k, v) for k, v in params.items())
    raise invalid("params: expected None, a 'NAME=VALUE,...' string or a dict, got %s"
                  % type(params).__name__)


def _export_frame(frame):
    f = ffi.new("lumis_export_frame *")
    check(iolib.lumis_export_frame_from_name(cstr(frame), f), "frame '%s'" % frame)
    return f[0]


class LightSet(Handle):
    """K directional lights that stand for a map (lumis_light_set), in `sets` interleaved
    sets (0 the original)."""

    def __init__(self, map, method="median-cut", count=0, sets=0, params=None):
        if not isinstance(map, Map):
            raise invalid("map: expected a lumis.Map, got %s" % type(map).__name__)
        if lib.lumis_lights_method_from_name(cstr(method), ffi.new("lumis_lights_method *")) != lib.LUMIS_OK:
            raise invalid("method: unknown light-set method '%s' (one of %s)" % (
                method, ", ".join(light_methods())))
        sink = Sink()
        p = ffi.new("lumis_light_params *")
        text = _params_text(params)
        if text:
            sink.check(lib.lumis_light_params_parse(p, cstr(text), sink.c), "params")
        sink.check(lib.lumis_light_params_check(p, cstr(method), sink.c), "params")
        out = ffi.new("lumis_light_set **")
        sink.check(lib.lumis_lights_by_name(map.ptr, cstr(method), count, sets, p, sink.c, out),
                   "lights %s" % method)
        super().__init__(out[0], lib.lumis_light_set_destroy)
        self.map = map
        self.method = method
        buf = ffi.new("char[1024]")
        lib.lumis_light_params_format(p, buf, 1024)
        self.params = pystr(buf)

    sets = property(lambda self: lib.lumis_light_set_sets(self.ptr))
    count = property(lambda self: lib.lumis_light_set_get_info(self.ptr).count)

    def lights(self, set_index=0):
        """The lights of one set as a numpy structured array (LIGHT_DTYPE: direction (3,)
        float32 towards the light, extent float32 radians, power (3,) float64 RGB radiance x
        sr, solid_angle float64 sr, pixels int32, kind int32 (LIGHT_KINDS)); a copy."""
        lights = ffi.new("lumis_light **")
        n = ffi.new("int *")
        check(lib.lumis_light_set_get(self.ptr, set_index, lights, n), "set %d" % set_index)
        if n[0] == 0:
            return np.zeros(0, dtype=LIGHT_DTYPE)
        return np.frombuffer(ffi.buffer(lights[0], n[0] * LIGHT_DTYPE.itemsize),
                             dtype=LIGHT_DTYPE).copy()

    directions = property(lambda self: np.ascontiguousarray(self.lights()["direction"]))
    power = property(lambda self: np.ascontiguousarray(self.lights()["power"]))

    def labels(self):
        """The light of every pixel: H x W int32 (row 0 the zenith), a copy."""
        w, h = ffi.new("int *"), ffi.new("int *")
        p = lib.lumis_light_set_labels(self.ptr, w, h)
        return np.frombuffer(ffi.buffer(p, w[0] * h[0] * 4), dtype=np.int32).copy().reshape(h[0], w[0])

    def info(self):
        """The build's report (lumis_light_set_info) as a dict."""
        i = lib.lumis_light_set_get_info(self.ptr)
        d = {k: getattr(i, k) for k in (
            "requested", "count", "direct", "indirect", "build_ms", "threshold",
            "percentile_luminance", "avg_luminance", "max_luminance", "emissive_pixels",
            "returned_pixels", "gamma_em", "gamma_nem", "budget", "mask_radius", "seeds",
            "kmeans_iterations", "kmeans_converged")}
        d["method"] = self.method
        d["power"] = list(i.power)
        d["kmeans_objective"] = [i.kmeans_objective[k] for k in range(i.kmeans_objective_count)]
        return d

    def irradiance(self, normal):
        """(the set's, the map's) irradiance in luminance on a diffuse surface of this normal."""
        se, me = ffi.new("double *"), ffi.new("double *")
        check(lib.lumis_light_set_irradiance(self.map.ptr, self.ptr, tuple(float(c) for c in normal),
                                             se, me), "irradiance")
        return se[0], me[0]

    def fold_below(self, up=(0.0, 1.0, 0.0)):
        """Folds the lights at or below the plane of normal `up` into the nearest above them
        (power kept); returns the report as a dict."""
        sink = Sink()
        rep = ffi.new("lumis_light_fold *")
        sink.check(lib.lumis_light_set_fold_below(self.ptr, tuple(float(c) for c in up), sink.c, rep),
                   "fold_below")
        return {"folded": rep.folded, "kept": rep.kept, "power": list(rep.power), "share": rep.share}

    def _export(self, fn, path, set_index, frame, masks, source, container):
        sink = Sink()
        # the strings live as long as these cdata objects, until the call returns
        method, params = ffi.new("char[]", cstr(self.method)), ffi.new("char[]", cstr(self.params or ""))
        src = ffi.new("char[]", cstr(source)) if source else ffi.NULL
        opts = ffi.new("lumis_light_export_options *", {
            "set_index": set_index, "masks": int(bool(masks)), "source": src, "method": method,
            "errors": sink.value, "parameters": params, "frame": _export_frame(frame),
            "container": container})
        sink.check(fn(cstr(path), self.ptr, opts), path)

    def write_json(self, path, set_index=0, frame="engine", masks=False, source=None):
        """The lights as `lumis lights --json` writes them (docs/lights-export.md)."""
        self._export(iolib.lumis_light_set_write_json, path, set_index, frame, masks, source, 0)

    def write_gltf(self, path, set_index=0, frame="engine", binary=None):
        """glTF 2.0 KHR_lights_punctual: .gltf text or .glb binary (from the path unless
        binary is given)."""
        container = 0 if binary is None else (2 if binary else 1)
        self._export(iolib.lumis_light_set_write_gltf, path, set_index, frame, False, None, container)


def lights(map, method="median-cut", count=0, sets=0, params=None):
    """K lights by a method's name with its parameters (a "NAME=VALUE,..." string or a
    dict, as `lumis lights --param`); 0 for count or sets: the method's default."""
    return LightSet(map, method, count, sets, params)


# ---- photometric files ---------------------------------------------------------------------

class Photometric(Handle):
    """An IES LM-63 or EULUMDAT file (lumis_photometric_file): its far-field table in
    candela, in the luminaire's frame (aim -z; docs/photometric.md)."""

    def __init__(self, path):
        sink = Sink()
        out = ffi.new("lumis_photometric_file **")
        sink.check(iolib.lumis_photometric_read(cstr(path), sink.c, out), path)
        super().__init__(out[0], iolib.lumis_photometric_file_destroy)
        f = out[0]
        self.path = path
        self.format = {1: "ies", 2: "ldt"}[int(f.format)]
        for k in ("standard", "manufacturer", "luminaire", "catalog", "lamp", "test", "warning"):
            setattr(self, k, pystr(getattr(f, k)))
        self.lamps, self.lumens_per_lamp = f.lamps, f.lumens_per_lamp
        self.input_watts, self.lamp_sets = f.input_watts, f.lamp_sets

    @property
    def _model(self):
        return self.ptr.model

    flux = property(lambda self: lib.lumis_photometric_flux(self._model))

    def info(self):
        """lumis_photometric_info as a dict (names as the tool's --json)."""
        i = ffi.new("lumis_photometric_info *")
        check(lib.lumis_photometric_get_info(self._model, i), self.path)
        d = {k: getattr(i, k) for k in (
            "width", "length", "height", "nv", "nh", "v_first", "v_last", "h_first", "h_last",
            "flux", "lamp_lumens", "luminaire_lumens", "max_candela", "max_h", "max_v",
            "downward_fraction")}
        d["type"] = pystr(lib.lumis_photometric_type_name(i.type))
        d["symmetry"] = pystr(lib.lumis_photometric_symmetry_name(i.symmetry))
        d["shape"] = pystr(lib.lumis_photometric_shape_name(i.shape))
        d["beam_deg"], d["field_deg"] = list(i.beam_deg), list(i.field_deg)
        return d

    def candela(self, h_deg, v_deg):
        """Intensity (cd) on the grid of horizontal x vertical angles (the table's own
        conventions; type C: h = C, v = gamma): len(h) x len(v) float64, one C call
        (lumis_photometric_intensity_at_n)."""
        h = np.ascontiguousarray(np.atleast_1d(np.asarray(h_deg, dtype=np.float64)).ravel())
        v = np.ascontiguousarray(np.atleast_1d(np.asarray(v_deg, dtype=np.float64)).ravel())
        out = np.empty((len(h), len(v)), dtype=np.float64)
        check(lib.lumis_photometric_intensity_at_n(self._model, _dptr(h), len(h), _dptr(v), len(v),
                                                   _dptr(out)), "%s: candela" % self.path)
        return out

    def intensity(self, directions):
        """Intensity (cd) towards each of N unit directions (luminaire frame): N float64, one
        C call (lumis_photometric_intensity_n)."""
        d = float_array(directions, np.float32, (3,), "directions")
        out = np.empty(d.shape[0], dtype=np.float64)
        check(lib.lumis_photometric_intensity_n(self._model, _vptr(d), d.shape[0], _dptr(out)),
              "%s: intensity" % self.path)
        return out

    def sample(self, u):
        """Directions in proportion to intensity from N pairs in [0, 1): (directions N x 3
        float32, pdf N float64 per steradian), one C call (lumis_photometric_sample_n)."""
        uu = float_array(u, np.float64, (2,), "u")
        n = uu.shape[0]
        d = np.empty((n, 3), dtype=np.float32)
        p = np.empty(n, dtype=np.float64)
        check(lib.lumis_photometric_sample_n(self._model, _dptr(uu), n, _vptr(d), _dptr(p)),
              "%s: sample" % self.path)
        return d, p

    def pdf(self, directions):
        """The pdf per steradian the sampler draws each of N directions with: N float64, one
        C call (lumis_photometric_pdf_n)."""
        d = float_array(directions, np.float32, (3,), "directions")
        out = np.empty(d.shape[0], dtype=np.float64)
        check(lib.lumis_photometric_pdf_n(self._model, _vptr(d), d.shape[0], _dptr(out)),
              "%s: pdf" % self.path)
        return out

    @property
    def type(self):
        """"C", "B" or "A" (LM-63's photometric type; docs/photometric.md, "Conventions")."""
        return self.info()["type"]

    def orient(self, aim, up=None, roll_deg=0.0):
        """The rotation R (3 x 3 float64, world = R local) that places this fixture aimed
        along `aim` in lumis's world (y up), as a scene file's "aim", "up" and "roll_deg" do:
        lumis_photometric_orient (liblumis-render.so; docs/photometric.md, "Aiming a
        fixture")."""
        from ._render import photometric_orient  # noqa: PLC0415 - the render library is optional
        return photometric_orient(self.type, aim, up, roll_deg)


def read_photometric(path):
    """Photometric(path): an .ies or .ldt file (told apart by content)."""
    return Photometric(path)


# ---- sequences -----------------------------------------------------------------------------

SEQUENCES = ("pcg", "halton", "sobol", "pmj02", "stratified", "zsobol")


def sequence(name, n, seed=0):
    """n points of a 2D sequence in [0, 1)^2 as an n x 2 float64 array:
    pcg: PCG32 seeded (seed, stream 0), two 53-bit doubles per point (the numbers `lumis
    sample --seed` uses); halton: bases 2 and 3 (unscrambled, seed unused); sobol: the
    Owen-scrambled (0,2) Sobol' points of seed; pmj02: progressive multi-jittered (0,2) points
    of seed (n a power of two up to 2^20); stratified, zsobol: the renderer's own (they exist
    only per pixel), pixel (0, 0)'s camera jitter in a render of seed planned for n samples
    (render_sequence(name, n, seed=seed, spp=n); needs liblumis-render.so)."""
    n = int(n)
    if n < 0:
        raise invalid("n: expected a count >= 0, got %d" % n)
    out = np.empty((n, 2), dtype=np.float64)
    if name == "pcg":
        rng = ffi.new("lumis_pcg32 *")
        lib.lumis_pcg32_seed(rng, seed, 0)
        if n:
            lib.lumis_pcg32_fill_doubles(rng, ffi.cast("double *", ffi.from_buffer(out)), 2 * n)
    elif name == "halton":
        ri = lib.lumis_radical_inverse
        for i in range(n):
            out[i] = (ri(0, i), ri(1, i))
    elif name == "sobol":
        u = ffi.new("double[2]")
        for i in range(n):
            lib.lumis_sobol02(i, seed, u)
            out[i] = (u[0], u[1])
    elif name == "pmj02":
        xy = np.empty(2 * n, dtype=np.uint32)
        check(lib.lumis_pmj02_generate(n, seed, ffi.cast("uint32_t *", ffi.from_buffer(xy)))
              if n else lib.LUMIS_ERR_INVALID_ARGUMENT,
              "pmj02: n = %d (a power of two, 1 to 2^20)" % n)
        out[:] = xy.reshape(n, 2) * (1.0 / 4294967296.0)
    elif name in ("stratified", "zsobol"):
        # the renderer's per-pixel sequences (lumis-render): pixel (0, 0)'s camera jitter
        # (dimension 0) of a render planned for n samples; lumis.render_sequence gives any
        # pixel, dimension and plan
        from ._render import render_sequence  # noqa: PLC0415 - the render library is optional
        return render_sequence(name, n, seed=seed, spp=n)
    else:
        raise invalid("sequence: unknown '%s' (one of %s)" % (name, ", ".join(SEQUENCES)))
    return out


def uniform(n, seed=1):
    """n pairs of uniform numbers as `lumis sample -n N --seed S` draws them (PCG32)."""
    return sequence("pcg", n, seed)


# ---- metrics -------------------------------------------------------------------------------

def _pair(reference, test):
    r, t = image_array(reference, "reference"), image_array(test, "test")
    if r.shape != t.shape:
        raise invalid("test: shape %s differs from the reference's %s" % (t.shape, r.shape))
    return r, t


def errors(reference, test, relmse_epsilon=0.0):
    """MSE, RMSE, relative MSE and PSNR on linear values (lumis_image_errors) as a dict."""
    r, t = _pair(reference, test)
    sink = Sink()
    opts = ffi.new("lumis_metric_options *", {"relmse_epsilon": relmse_epsilon, "errors": sink.value})
    st = ffi.new("lumis_image_error_stats *")
    sink.check(lib.lumis_image_errors(image_struct(r), image_struct(t), opts, st), "errors")
    return {k: getattr(st, k) for k in ("mse", "rmse", "relmse", "relmse_epsilon", "psnr", "psnr_peak")}


def delta_e(reference, test, exposure_ev=0.0, map=False):
    """Mean CIE76 Delta E (and the H x W map with map=True)."""
    r, t = _pair(reference, test)
    sink = Sink()
    opts = ffi.new("lumis_metric_options *", {"exposure_ev": exposure_ev, "errors": sink.value})
    mean = ffi.new("double *")
    m = np.empty(r.shape[:2], dtype=np.float32) if map else None
    sink.check(lib.lumis_lab_delta_e(image_struct(r), image_struct(t), opts,
                                     ffi.cast("float *", ffi.from_buffer(m)) if map else ffi.NULL,
                                     mean), "delta_e")
    return (mean[0], m) if map else mean[0]


def flip(reference, test, hdr=True, pixels_per_degree=0.0, map=False, exposure_ev=0.0):
    """Mean FLIP error: HDR-FLIP (default) or LDR-FLIP (hdr=False, of the values x
    2^exposure_ev, clamped to [0, 1] by the library); with map=True also the H x W error
    map."""
    r, t = _pair(reference, test)
    if not hdr and exposure_ev != 0.0:
        k = np.float32(2.0 ** exposure_ev)
        r, t = r * k, t * k
    sink = Sink()
    opts = ffi.new("lumis_flip_options *", {"pixels_per_degree": pixels_per_degree,
                                            "errors": sink.value})
    m = np.empty(r.shape[:2], dtype=np.float32) if map else None
    mp = ffi.cast("float *", ffi.from_buffer(m)) if map else ffi.NULL
    if hdr:
        res = ffi.new("lumis_flip_hdr_result *")
        sink.check(lib.lumis_flip_hdr(image_struct(r), image_struct(t), opts, mp, ffi.NULL, res),
                   "flip (hdr)")
        mean = res.mean
    else:
        mp_mean = ffi.new("double *")
        sink.check(lib.lumis_flip_ldr(image_struct(r), image_struct(t), opts, mp, mp_mean),
                   "flip (ldr)")
        mean = mp_mean[0]
    return (mean, m) if map else mean


def compare(reference, test, exposure_ev=0.0, relmse_epsilon=0.0):
    """Every metric of `lumis compare --json --exposure EV`: rmse, relmse, psnr, lab_delta_e
    and flip_ldr (display-referred: values x 2^exposure_ev clamped to [0, 1]), flip_hdr (and
    mse)."""
    e = errors(reference, test, relmse_epsilon)
    return {"mse": e["mse"], "rmse": e["rmse"], "relmse": e["relmse"], "psnr": e["psnr"],
            "lab_delta_e": delta_e(reference, test, exposure_ev),
            "flip_ldr": flip(reference, test, hdr=False, exposure_ev=exposure_ev),
            "flip_hdr": flip(reference, test, hdr=True)}
