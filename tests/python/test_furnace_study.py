"""furnace() and study() give the command line's rows (timings aside)."""
import json

import pytest

TIMING = {"seconds", "cpu_seconds", "cost", "seconds_per_estimate", "efficiency", "efficiency_relmse"}


def without_timing(rows):
    return [{k: v for k, v in r.items() if k not in TIMING} for r in rows]


def test_furnace_rows_equal_cli_json(sym, cli, tmp_path):
    out = tmp_path / "f.json"
    cli("furnace", "-e", "cosine,symmetric,paper", "--environment", "constant,disk", "--n", "1,100", "--theta", "0,60",
        "-M", 300, "--seed", 5, "--sampler", "independent", "--symmetric-n", 2, "--disk-radius", 20, "--json", out)
    expected = json.loads(out.read_text())
    rows = sym.furnace(estimators=["cosine", "symmetric", "paper"], environments="constant,disk", n=[1, 100], theta=(0, 60),
                       repeats=300, seed=5, sampler="independent", symmetric_n=2, disk_radius=20)
    assert len(rows) == 2 * 2 * 2 * 3
    assert without_timing(rows) == without_timing(expected)
    assert all(r["seconds_per_estimate"] > 0 for r in rows)


def test_furnace_grid_and_defaults(sym, cli, tmp_path):
    out = tmp_path / "g.json"
    cli("furnace", "-e", "phong", "--grid", "-M", 50, "--json", out)
    rows = sym.furnace(estimators="phong", grid=True, repeats=50)
    assert [(r["n"], r["theta_deg"]) for r in rows] == [(n, t) for n in (1, 10, 100, 1000, 10000) for t in (0, 30, 60, 85)]
    assert without_timing(rows) == without_timing(json.loads(out.read_text()))


def test_furnace_is_unbiased_on_constant_environment(sym):
    """Default sampler, 4000 estimates: every unbiased estimator within 4 standard errors of the exact value."""
    for r in sym.furnace(estimators="cosine,phong,symmetric,symmetric-shifted", repeats=4000, seed=3):
        assert abs(r["estimate"] - r["exact"]) < 4 * r["std_error"], r


STUDY = ["--estimators", "cosine,symmetric", "--spp", "1,2", "-R", 2, "-W", 16, "-H", 12, "--reference-spp", 16, "--seed", 4,
         "--no-plots", "-t", 2]


def test_study_rows_equal_cli_rows(sym, cli, tmp_path):
    cli("study", "cornell", *STUDY, "-o", tmp_path / "cli")
    expected = json.loads((tmp_path / "cli" / "results.json").read_text())["rows"]
    rows, report = sym.study("cornell", estimators=["cosine", "symmetric"], spp=[1, 2], repeats=2, width=16, height=12,
                             reference_spp=16, seed=4, plots=False, threads=2, out=str(tmp_path / "py"))
    assert len(rows) == 2 * 2 * 2
    assert without_timing(rows) == without_timing(expected)
    assert report == str(tmp_path / "py" / "report.md")
    assert "cosine" in (tmp_path / "py" / "report.md").read_text()
    # The Scene object names its spec; the study reuses the cached reference.
    rows2, _ = sym.study(sym.load_scene("cornell"), estimators="cosine,symmetric", spp=(1, 2), repeats=2, width=16, height=12,
                         reference_spp=16, seed=4, plots=False, out=str(tmp_path / "py"))
    assert without_timing(rows2) == without_timing(rows)


def test_study_takes_the_cost_and_repeat_keywords_of_the_schema(sym, cli, tmp_path):
    """cost, orbits, target_interval, max_repeats and time are keywords of study(), as on the command line:
    the same rows (timing aside), efficiency over rays, and the answer's fair pair."""
    args = dict(estimators="phong,symmetric-mix", symmetric_modes="branch,spread", splits=[2], split_estimators="phong", orbits=[2],
                spp=[4], repeats=2, width=12, height=12, reference_spp=32, seed=2, cost="rays", target_interval=0.001,
                max_repeats=3, plots=False, threads=1)
    rows, report = sym.study("cornell", out=str(tmp_path / "py"), **args)
    cli("study", "cornell", "--estimators", "phong,symmetric-mix", "--symmetric-modes", "branch,spread", "--splits", 2,
        "--split-estimators", "phong", "--orbits", 2, "--spp", 4, "-R", 2, "-W", 12, "-H", 12, "--reference-spp", 32, "--seed", 2,
        "--cost", "rays", "--target-interval", 0.001, "--max-repeats", 3, "--no-plots", "-t", 1, "-o", tmp_path / "cli")
    expected = json.loads((tmp_path / "cli" / "results.json").read_text())
    assert without_timing(rows) == without_timing(expected["rows"])
    assert {r["variant"] for r in rows} == {"phong", "phong+split2", "symmetric-mix+orbit2", "symmetric-mix+spread"}
    assert all(r["cost"] == r["rays"] and r["efficiency"] == pytest.approx(1 / (r["mse"] * r["rays"])) for r in rows)
    assert all(sum(1 for r in rows if r["variant"] == v) == 3 for v in {r["variant"] for r in rows}), "--max-repeats 3"
    assert expected["stopped_by"] == "max-repeats"
    text = (tmp_path / "py" / "report.md").read_text()
    assert "`symmetric-mix+orbit2` against `phong+split2` (2 paths per camera sample)" in text
    assert "1/(MSE x rays traced)" in text
    with pytest.raises(ValueError, match="unknown cost 'seconds'"):
        sym.study("cornell", cost="seconds", out=str(tmp_path / "bad"))
