"""Bad inputs raise lumis.Error subclasses carrying the status and the library's message."""
import numpy as np
import pytest

import lumis


def test_missing_file():
    with pytest.raises(lumis.OpenError) as e:
        lumis.read_map("/nonexistent/x.exr")
    assert e.value.status_name == "open" and "/nonexistent/x.exr" in str(e.value)
    assert isinstance(e.value, lumis.Error) and isinstance(e.value, OSError)


def test_corrupt_and_truncated_files(tmp_path):
    bad = tmp_path / "bad.hdr"
    bad.write_bytes(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 4 +X 4\n\x02\x02")
    with pytest.raises(lumis.FormatError) as e:
        lumis.read_map(str(bad))
    assert e.value.status_name in ("truncated", "corrupt") and "bad.hdr" in e.value.message
    junk = tmp_path / "junk.exr"
    junk.write_bytes(b"this is no image at all")
    with pytest.raises(lumis.FormatError):
        lumis.read_image(str(junk))
    empty = tmp_path / "empty.pfm"
    empty.write_bytes(b"")
    with pytest.raises(lumis.EmptyFileError):
        lumis.read_map(str(empty))
    ies = tmp_path / "bad.ies"
    ies.write_text("IESNA:LM-63-2002\nTILT=NONE\n1 1000 1 2 1 1 2 0 0 0\n")
    with pytest.raises(lumis.Error) as e:
        lumis.read_photometric(str(ies))
    assert "bad.ies" in e.value.message


def test_bad_specs_and_names():
    with pytest.raises(lumis.Error):
        lumis.read_map("sky:0x5")
    with lumis.read_map("sky:16x8") as m:
        with pytest.raises(lumis.InvalidArgumentError, match="no-such"):
            lumis.Sampler(m, "no-such")
        with pytest.raises(lumis.InvalidArgumentError, match="importance"):
            lumis.Sampler(m, importance="loudness")
    with pytest.raises(lumis.InvalidArgumentError, match="lumis.Map"):
        lumis.Sampler("sky:16x8")
    with pytest.raises(lumis.InvalidArgumentError, match="unknown 'nope'"):
        lumis.sequence("nope", 4)
    with pytest.raises(lumis.InvalidArgumentError, match="pmj02"):
        lumis.sequence("pmj02", 3)


def test_wrong_shapes_and_dtypes():
    with lumis.read_map("sky:16x8") as m, lumis.Sampler(m) as s:
        with pytest.raises(lumis.InvalidArgumentError, match=r"shape \(N, 2\)"):
            s.sample(np.zeros((4, 3)))
        with pytest.raises(lumis.InvalidArgumentError, match="dtype int64"):
            s.sample(np.zeros((4, 2), dtype=np.int64))
        with pytest.raises(lumis.InvalidArgumentError, match=r"shape \(N, 3\)"):
            s.pdf(np.zeros(3, dtype=np.float32))
        with pytest.raises(lumis.InvalidArgumentError, match="complex"):
            s.pdf(np.zeros((2, 3), dtype=np.complex64))
        # float32 u and float64 directions are converted, not refused
        d, p = s.sample(lumis.uniform(8).astype(np.float32))
        assert np.array_equal(s.pdf(d.astype(np.float64)), s.pdf(d))
        # empty batches
        d0, p0 = s.sample(np.zeros((0, 2)))
        assert d0.shape == (0, 3) and p0.shape == (0,)
    with pytest.raises(lumis.InvalidArgumentError, match=r"\(H, W, 3\)"):
        lumis.Map(np.zeros((4, 4), dtype=np.float32))
    with pytest.raises(lumis.InvalidArgumentError, match="dtype uint8"):
        lumis.Map(np.zeros((4, 8, 3), dtype=np.uint8))
    with pytest.raises(lumis.InvalidArgumentError, match="differs"):
        lumis.compare(np.zeros((4, 4, 3)), np.zeros((4, 5, 3)))


def test_closed_objects_refuse_use():
    m = lumis.read_map("sky:16x8")
    s = lumis.Sampler(m)
    m.close()
    d, p = s.sample(lumis.uniform(4))  # the sampler keeps the C map alive
    assert np.all(p > 0)
    s.close()
    s.close()  # idempotent
    with pytest.raises(lumis.InvalidArgumentError, match="after close"):
        s.sample(lumis.uniform(4))
    with pytest.raises(lumis.InvalidArgumentError, match="after close"):
        m.info()


def test_warnings_reach_python():
    with lumis.Map(np.zeros((8, 16, 3), dtype=np.float32)) as m:
        with pytest.warns(lumis.Warning):
            s = lumis.Sampler(m, "alias")
        assert s.uniform_fallback
        s.close()
