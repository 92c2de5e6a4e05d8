"""lumis.bench: a bench suite run by the tool (a subprocess, docs/python.md), its items read
back as records equal to the tool's own results files."""
import csv
import json
import os

import pytest

import lumis

SUITE = {
    "name": "py-tiny",
    "description": "two methods, one spp budget, a tiny image: the records' fields",
    "maps": ["sky:32x16"],
    "scenes": ["spheres"],
    "methods": [{"method": "inversion"}, {"method": "bsdf", "mis": "none"}],
    "budgets": [{"spp": 2}, {"spp": 4}],
    "reference": {"spp": 16, "method": "inversion"},
    "size": [24, 16],
    "seed": 3,
    "exposure_ev": -4,
}


def test_bench_records_are_the_tools_results(cli, tmp_path):
    suite = tmp_path / "tiny.json"
    suite.write_text(json.dumps(SUITE))
    out = tmp_path / "out"
    tool = os.environ.get("LUMIS_CLI")
    recs = lumis.bench(str(suite), str(out), threads=1, tool=tool)
    assert isinstance(recs, lumis.BenchRecords) and len(recs) == 4
    assert recs.summary["suite"] == "py-tiny" and recs.summary["items_done"] == 4
    with open(out / "results.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert [(r["map"], r["scene"], r["method"], r["budget"]) for r in recs] == \
        [(r["map"], r["scene"], r["method"], r["budget"]) for r in rows]
    for rec, row in zip(recs, rows):
        assert rec["suite"] == "py-tiny" and rec["spp"] == int(row["spp"])
        for k in ("rmse", "relmse", "psnr", "lab_delta_e", "flip_ldr", "flip_hdr"):
            assert rec[k] == pytest.approx(float(row[k]), rel=1e-6), k
    assert {r["method"] for r in recs} == {"inversion", "bsdf"}
    assert {r["budget"] for r in recs} == {"spp2", "spp4"}
    # run again: every item is kept (the tool resumes), the same records
    again = lumis.bench(str(suite), str(out), threads=1, tool=tool)
    assert again == recs
    assert lumis.read_bench(str(out)) == recs


def test_bench_refusals(tmp_path):
    with pytest.raises(lumis.InvalidArgumentError, match="no file"):
        lumis.bench(str(tmp_path / "missing.json"))
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(dict(SUITE, methods=[{"method": "no-such-sampler"}])))
    tool = os.environ.get("LUMIS_CLI")
    with pytest.raises(lumis.Error, match="no-such-sampler"):
        lumis.bench(str(bad), str(tmp_path / "o"), tool=tool)
