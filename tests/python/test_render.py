"""lumis.render (lumis_render_session) against `lumis render` with the same settings: the
same image bit for bit (the EXR read back with the package), the library's refusals as
lumis.Error with its message, and no growth over repeated renders."""
import gc
import os

import numpy as np
import pytest

import lumis

pytestmark = pytest.mark.skipif(lumis._lib.renderlib is None,
                                reason="no liblumis-render.so (make run)")


def tool_render(cli, tmp_path, name, *args):
    out = tmp_path / ("%s.exr" % name)
    cli("render", *args, "-o", out, "--no-sidecar", "--quiet")
    return lumis.read_image(str(out))


CASES = [
    # (lumis.render keywords, the tool's options)
    ({"scene": "spheres", "env": "sky:64x32", "size": (48, 32), "spp": 4, "seed": 3,
      "auto": False},
     ["--scene", "spheres", "--env", "sky:64x32", "--size", "48x32", "--spp", "4", "--seed", "3",
      "--no-auto"]),
    # the default: the automatic estimator, predicted from the surfaces the camera sees (no
    # pilots, no timing: the same choice on both sides)
    ({"scene": "spheres", "env": "sky:64x32", "size": (48, 32), "spp": 4, "seed": 3},
     ["--scene", "spheres", "--env", "sky:64x32", "--size", "48x32", "--spp", "4", "--seed", "3"]),
    ({"scene": "ward-aniso", "env": "studio:64x32", "method": "kdtree", "estimator": "light",
      "size": (40, 30), "spp": 3, "sequence": "halton"},
     ["--scene", "ward-aniso", "--env", "studio:64x32", "--method", "kdtree", "--mis", "none",
      "--size", "40x30", "--spp", "3", "--sequence", "halton"]),
    ({"scene": "bunny-plane", "env": "sky:64x32", "lights": "median-cut", "lights_k": 8,
      "size": (40, 30), "spp": 2},
     ["--scene", "bunny-plane", "--env", "sky:64x32", "--lights", "median-cut", "--lights-k",
      "8", "--size", "40x30", "--spp", "2"]),
    ({"scene": "spheres", "env": "sky:64x32", "lights": "variance-min", "lights_k": 8,
      "lights_mode": "stratified", "size": (40, 30), "spp": 2, "seed": 7},
     ["--scene", "spheres", "--env", "sky:64x32", "--lights", "variance-min", "--lights-k", "8",
      "--lights-mode", "stratified", "--size", "40x30", "--spp", "2", "--seed", "7"]),
    ({"scene": "spheres", "env": "sky:64x32", "lights": "median-cut", "lights_k": 16,
      "lights_mode": "stratified", "lights_draws": 3, "size": (40, 30), "spp": 2, "seed": 7},
     ["--scene", "spheres", "--env", "sky:64x32", "--lights", "median-cut", "--lights-k", "16",
      "--lights-mode", "stratified", "--lights-draws", "3", "--size", "40x30", "--spp", "2",
      "--seed", "7"]),
]


@pytest.mark.parametrize("kw,args", CASES, ids=["env", "auto-default", "kdtree-light-halton",
                                                "light-set", "stratified", "selected-draws"])
def test_render_equals_the_tool_bit_for_bit(cli, tmp_path, kw, args):
    img, r = lumis.render(**kw)
    ref = tool_render(cli, tmp_path, "ref", *args)
    assert img.dtype == np.float32 and img.shape == ref.shape == (kw["size"][1], kw["size"][0], 3)
    assert np.array_equal(img, ref)
    assert img.max() > 0
    assert r["spp"] == kw["spp"] and r["width"] == kw["size"][0]
    assert r["lighting"] == ("light-set" if "lights" in kw else "env")
    if "lights" in kw:
        assert r["lights_k"] == kw["lights_k"]
    # the automatic estimator when no argument fixes the estimator (the tool's default)
    fixed = "auto" in kw or any(k in kw for k in ("method", "estimator", "lights"))
    assert (r["auto"] is None) == fixed
    if not fixed:
        # the spheres reflect 47 % diffusely, under the strata's 50 %: MIS
        a = r["auto"]
        assert a["mode"] == "predict" and a["chosen"] == "mis" and a["prior"] == 0
        assert 0.3 < a["diffuse_share"] < 0.5 and a["rays_met"] > 0
        assert r["lights_k"] == 0 and len(a["candidates"]) == 6


def test_auto_runs_its_pilots_and_reports_them():
    img, r = lumis.render("spheres", env="sky:64x32", size=(32, 24), spp=64, threads=1,
                          auto="pilots")
    a = r["auto"]
    assert a["mode"] == "pilots" and a["diffuse_share"] is None
    assert a["prior"] == 0 and a["pilot_cap_seconds"] > 0
    measured = [c for c in a["candidates"] if c["measured"]]
    assert len(measured) >= 2 and a["chosen"] in [c["name"] for c in measured]
    best = min(measured, key=lambda c: c["relmse_x_seconds"])
    assert a["chosen"] == best["name"]
    _, off = lumis.render("spheres", env="sky:64x32", size=(32, 24), spp=2, auto=False)
    assert off["auto"] is None
    with pytest.raises(lumis.Error):
        lumis.render("spheres", env="sky:64x32", size=(32, 24), spp=2, auto="yes")


def test_photometric_scene_file_equals_the_tool(cli, root, tmp_path):
    scene = os.path.join(root, "docs", "examples", "photometric", "fixtures.json")
    img, r = lumis.render(scene, size=(40, 30), spp=2)
    assert r["lighting"] == "photometric"
    ref = tool_render(cli, tmp_path, "fixtures", scene, "--size", "40x30", "--spp", "2")
    assert np.array_equal(img, ref)


def test_a_map_object_and_a_different_seed():
    with lumis.read_map("sky:64x32") as m:
        a, _ = lumis.render("spheres", env=m, size=(32, 24), spp=2, seed=1)
        b, _ = lumis.render("spheres", env=m, size=(32, 24), spp=2, seed=1)
        c, _ = lumis.render("spheres", env=m, size=(32, 24), spp=2, seed=2)
    assert np.array_equal(a, b) and not np.array_equal(a, c)


def test_time_budget_reports_what_it_spent():
    img, r = lumis.render("spheres", env="sky:64x32", size=(32, 24), time_budget=0.3)
    assert img.shape == (24, 32, 3)
    assert r["spp"] >= 1 and r["passes"] >= 1 and r["time_budget"] == 0.3
    assert 0 < r["budget_used_seconds"] < 5


@pytest.mark.parametrize("kw,words", [
    ({"scene": "no-such-scene"}, ["no-such-scene", "spheres"]),
    ({"scene": "/nonexistent/scene.json"}, ["/nonexistent/scene.json"]),
    ({"env": "/nonexistent.exr"}, ["/nonexistent.exr"]),
    ({"method": "no-such-sampler"}, ["no-such-sampler"]),
    ({"estimator": "both"}, ["estimator", "both"]),
    ({"lights": "no-such-method"}, ["no-such-method"]),
    ({"lights": "median-cut", "lights_params": "nonsense=1"}, ["nonsense"]),
    ({"lights_mode": "sometimes"}, ["sometimes"]),
    ({"lights": "median-cut", "lights_draws": 4}, ["lighting.light_set.draws"]),  # point mode
    ({"upsample": 2}, ["upsample"]),                         # only with Wu's light sets
    ({"bounces": 1, "lights": "median-cut"}, ["max_bounces"]),  # point lights: direct only
    ({"sequence": "no-such-sequence"}, ["no-such-sequence"]),
    ({"size": (0, 10)}, ["size"]),
])
def test_refusals_carry_the_library_message(kw, words):
    args = {"scene": "spheres", "env": "sky:32x16", "size": (16, 12), "spp": 1}
    args.update(kw)
    with pytest.raises(lumis.Error) as e:
        lumis.render(**args)
    for w in words:
        assert w in str(e.value), (w, str(e.value))


def rss_kib():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * 4096 // 1024


def test_no_growth_over_repeated_renders():
    # the bunny's scene (Embree's BVH, MBs), a 128 x 64 map (98 KiB), the image (144 KiB): a
    # leak of any of them per render shows
    def once():
        lumis.render("spheres", env="sky:128x64", size=(128, 96), spp=1, threads=1)
        lumis.render("bunny-plane", env="sky:128x64", size=(16, 12), spp=1, threads=1,
                     lights="median-cut", lights_k=4)
    for _ in range(10):  # warm up: Embree's and OpenMP's pools, cffi's caches
        once()
    gc.collect()
    before = rss_kib()
    for _ in range(100):
        once()
    gc.collect()
    grown = rss_kib() - before
    # a leaked scene, map, sampler, light set or image per render is > 30 KiB: > 6 MB in all
    assert grown < 4096, "RSS grew by %d KiB over 200 renders" % grown


def test_the_interpreter_exits_cleanly_after_a_render(root):
    """The interpreter's exit frees cffi's lib objects, which closed the libraries: libgomp
    (and Embree's TBB) were unmapped under their idle worker threads, and the process died
    of SIGSEGV at exit (lumis/_lib.py, _DLFLAGS).  OMP_WAIT_POLICY=ACTIVE keeps the workers
    spinning in libgomp's code: every such exit crashed before the fix (10 of 10); the
    library's default policy crashed 3-5 % of them."""
    import subprocess  # noqa: PLC0415
    import sys  # noqa: PLC0415
    code = ("import lumis; img, r = lumis.render('spheres', env='sky:32x16', size=(16, 12), "
            "spp=1); print(img.shape)")
    env = dict(os.environ, PYTHONPATH=os.path.join(root, "python") + os.pathsep +
               os.environ.get("PYTHONPATH", ""))
    for policy in ["ACTIVE"] * 4 + [None] * 4:
        e = dict(env)
        e.pop("OMP_WAIT_POLICY", None)
        if policy:
            e["OMP_WAIT_POLICY"] = policy
        r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=e)
        assert r.returncode == 0 and "(12, 16, 3)" in r.stdout, (policy, r.returncode, r.stderr)


FIXTURE_CASES = [
    # (fixtures=, the tool's options): one fixture as --fixture places it (an asymmetric
    # table, so that the roll and the up show)
    ([{"path": "road-asymmetric.ies", "at": (-1.0, 3.0, 0.5), "aim": (-0.5, 0, 0.2),
       "multiplier": 0.05, "roll_deg": 20}],
     ["--fixture", "road-asymmetric.ies", "--fixture-at", "-1,3,0.5", "--fixture-aim", "-0.5,0,0.2",
      "--fixture-multiplier", "0.05", "--fixture-roll", "20"]),
    ([lumis.Fixture("road-asymmetric.ies", at=(0.5, 3.2, 0.0), up=(1, 0, 1), area=True,
                    multiplier=0.03)],
     ["--fixture", "road-asymmetric.ies", "--fixture-at", "0.5,3.2,0", "--fixture-up", "1,0,1",
      "--fixture-area", "--fixture-multiplier", "0.03"]),
]


@pytest.mark.parametrize("fixtures,args", FIXTURE_CASES, ids=["aimed-rolled", "up-area"])
def test_fixture_placement_equals_the_tool(cli, root, tmp_path, fixtures, args):
    """fixtures= builds the lighting value --fixture's options build: the same image bit for
    bit (same seed, spp, one thread), the scene's own map ignored as the tool ignores it."""
    d = os.path.join(root, "docs", "examples", "photometric")
    fx = [dict(f, path=os.path.join(d, f["path"])) if isinstance(f, dict)
          else lumis.Fixture(os.path.join(d, f.path), f.at, f.aim, f.up, f.roll_deg,
                             f.multiplier, f.area) for f in fixtures]
    args = [os.path.join(d, a) if a.endswith(".ies") else a for a in args]
    img, r = lumis.render("spheres", fixtures=fx, size=(40, 30), spp=3, seed=5, threads=1)
    assert r["lighting"] == "photometric" and img.max() > 0
    ref = tool_render(cli, tmp_path, "fixture", "--scene", "spheres", *args, "--size", "40x30",
                      "--spp", "3", "--seed", "5", "--threads", "1")
    assert np.array_equal(img, ref)
    # the placement matters: the same fixture elsewhere is another image
    moved = [dict(vars(f)) if isinstance(f, lumis.Fixture) else dict(f) for f in fx]
    moved[0]["at"] = (moved[0]["at"][0] + 0.5, moved[0]["at"][1], moved[0]["at"][2])
    other, _ = lumis.render("spheres", fixtures=moved, size=(40, 30), spp=3, seed=5, threads=1)
    assert not np.array_equal(img, other)


def test_fixture_and_luminaire_refusals(root):
    ies = os.path.join(root, "docs", "examples", "photometric", "spot-cos10.ies")
    base = {"scene": "spheres", "size": (16, 12), "spp": 1}
    for fx, words in [({"path": ies, "at": (0, 3)}, ["fixtures[0].at"]),
                      ({"path": ies, "at": (0, 3, 0), "aim": (0, 3, 0)}, ["fixtures[0].aim"]),
                      ({"path": ies, "at": (0, 3, 0), "up": (0, 1, 0)}, ["fixtures[0].up"]),
                      ({"path": ies, "at": (0, 3, 0), "multiplier": 0}, ["multiplier"]),
                      ({"path": ies, "at": (0, 3, 0), "colour": 1}, ["fixtures[0]", "colour"]),
                      ({"path": "/nonexistent.ies", "at": (0, 3, 0)}, ["/nonexistent.ies"])]:
        with pytest.raises(lumis.Error) as e:
            lumis.render(fixtures=[fx], **base)
        for w in words:
            assert w in str(e.value), (w, str(e.value))
    with pytest.raises(lumis.InvalidArgumentError, match="places no luminaire"):
        lumis.render(luminaire="preset:small", **base)
    with pytest.raises(lumis.InvalidArgumentError, match="preset:nope"):
        lumis.render(luminaire="preset:nope", **base)


def test_luminaire_replacement_equals_the_tool(cli, tmp_path):
    """luminaire= replaces the scene's luminaires as --luminaire does: the same image."""
    kw = dict(size=(32, 24), spp=2, seed=4, threads=1)
    img, r = lumis.render("headlight", luminaire="preset:small", **kw)
    assert r["lighting"] == "luminaires" and img.max() > 0
    ref = tool_render(cli, tmp_path, "lum", "--scene", "headlight", "--luminaire", "preset:small",
                      "--size", "32x24", "--spp", "2", "--seed", "4", "--threads", "1")
    assert np.array_equal(img, ref)
    # the scene's own luminaire (the car's; the tool keeps it in its cache) is another image
    own = tool_render(cli, tmp_path, "own", "--scene", "headlight", "--size", "32x24", "--spp",
                      "2", "--seed", "4", "--threads", "1")
    assert not np.array_equal(img, own)
