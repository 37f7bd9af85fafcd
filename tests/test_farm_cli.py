"""The render farm without Blender (issue 25): both OpenJD templates validate; the morph bundle
run by `openjd run` on small procedural pairs (one of them refused by the morph) and its summary
checked against the pairs' reports; pair lists; frame files with UVs, normals and materials."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import animanifold as am
from animanifold import cli, mesh_export, morph_batch
from helpers import shapes
from helpers.shared_files import shared_mesh

ROOT = Path(__file__).resolve().parents[1]
OPENJD = shutil.which("openjd")
NO_OPENJD = "openjd-cli (pip install openjd-cli, scripts/install-deps.sh) is not installed"
TEMPLATES = sorted((ROOT / "farm" / "openjd").glob("*/template.yaml"))


def package_env():
    return dict(os.environ, PYTHONPATH=str(ROOT / "python"))


@pytest.mark.skipif(OPENJD is None, reason=NO_OPENJD)
@pytest.mark.parametrize("template", TEMPLATES, ids=lambda p: p.parent.name)
def test_openjd_check_validates_the_template(template):
    proc = subprocess.run([OPENJD, "check", str(template)], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "passes validation" in proc.stdout


def test_both_bundles_are_there():
    assert [p.parent.name for p in TEMPLATES] == ["bake", "morph"]


@pytest.fixture()
def pairs(tmp_path):
    """Four pairs in tmp_path/pairs/pairs.json: three procedural morphs and an open triangle,
    which the morph refuses."""
    folder = tmp_path / "pairs"
    folder.mkdir()
    am.write_mesh(folder / "sphere.off", *shapes.icosphere(1))
    am.write_mesh(folder / "cube.off", *shapes.cube())
    am.write_mesh(folder / "cylinder.off", *shapes.cylinder(12))
    am.write_mesh(folder / "torus.off", *shapes.torus(major=12, minor=6))
    am.write_mesh(folder / "open.off", np.eye(3), np.array([[0, 1, 2]]))
    rows = [{"source": "sphere.off", "target": "cube.off", "frames": 4, "method": "skeleton"},
            {"source": "cube.off", "target": "cylinder.off", "frames": 3, "method": "strip"},
            {"source": "torus.off", "target": "sphere.off", "frames": 4, "method": "skeleton", "name": "torus_sphere"},
            {"source": "open.off", "target": "cube.off", "frames": 3, "method": "skeleton", "name": "open"}]
    path = folder / "pairs.json"
    path.write_text(json.dumps(rows))
    return path


def summary_table(text: str) -> dict[str, dict[str, str]]:
    lines = [ln for ln in text.splitlines() if ln.startswith("|")]
    header = [c.strip() for c in lines[0].strip("|").split("|")]
    rows = [dict(zip(header, (c.strip() for c in ln.strip("|").split("|")))) for ln in lines[2:]]
    return {r["pair"]: r for r in rows}


def run_morph_bundle(pairs: Path, count: int, out: Path) -> None:
    proc = subprocess.run([OPENJD, "run", str(ROOT / "farm" / "openjd" / "morph" / "template.yaml"),
                           "-p", f"PairsFile={pairs}", "-p", f"PairCount={count}", "-p", f"OutputDir={out}",
                           "-p", f"Python={sys.executable}"],
                          capture_output=True, text=True, timeout=600, cwd=str(out.parent), env=package_env())
    assert proc.returncode == 0, proc.stdout[-4000:] + proc.stderr[-2000:]


def check_summary_against_reports(out: Path) -> dict[str, dict[str, str]]:
    """Every row of OUT/summary.md says what its pair's report.json says; the table, by pair."""
    table = summary_table((out / "summary.md").read_text())
    yes = {True: "yes", False: "no"}
    for name, row in table.items():
        report = json.loads((out / name / "report.json").read_text())
        assert row["status"] == report["status"]
        if report["status"] != "ok":
            assert f"**{name}**: {report['error']}" in (out / "summary.md").read_text()
            continue
        v = report["validity"]
        assert row["ends_reproduced"] == yes[v["ends_reproduced"]]
        assert row["inverted_simplices"] == str(v["inverted_simplices"])
        assert row["frames_cross_themselves"] == yes[v["frames_cross_themselves"]]
        assert row["bubble_frames"] == str(len(v.get("bubble_frames") or []))
        assert row["is_oriented_manifold"] == yes[report["is_oriented_manifold"]]
        assert row["tets"] == str(report["tets"]) == str(len(am.load(out / name / "morph.amf").simplices))
        assert row["morph_seconds"] == f"{report['seconds']['morph']:.2f}"
        assert row["total_seconds"] == f"{report['total_seconds']:.2f}"
        assert row["contact_sheet"] == f"![{name}/contact_sheet.png]({name}/contact_sheet.png)"
        assert (out / name / "contact_sheet.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        frames = sorted((out / name / "frames").iterdir())
        assert len(frames) == report["pair"]["frames"]
        assert all(f.read_text().count("\nvn ") > 0 for f in frames)
    assert not list(out.rglob(".*.tmp*")), "temporary files left behind"
    return table


@pytest.mark.skipif(OPENJD is None, reason=NO_OPENJD)
def test_morph_bundle_summary_agrees_with_every_report(pairs, tmp_path):
    out = tmp_path / "out"
    run_morph_bundle(pairs, 4, out)
    table = check_summary_against_reports(out)
    assert list(table) == ["001_sphere_to_cube", "002_cube_to_cylinder", "torus_sphere", "open"]
    assert [r["status"] for r in table.values()] == ["ok", "ok", "ok", "failed"]
    failure = json.loads((out / "open" / "report.json").read_text())["error"]
    assert failure.startswith("open.off -> cube.off: ") and "open" in failure[20:], failure


@pytest.mark.slow
@pytest.mark.skipif(OPENJD is None, reason=NO_OPENJD)
def test_morph_bundle_on_shared_pairs(shared_data, tmp_path):
    knight, torus800, torus = (shared_mesh(shared_data, n) for n in ("decimated-knight.off", "torus-800.off", "torus.obj"))
    pairs = tmp_path / "pairs.csv"
    pairs.write_text("source,target,frames,method\n"
                     f"{torus800},{knight},3,strip\n{torus},{knight},3,strip\n{knight},{torus800},3,skeleton\n")
    out = tmp_path / "out"
    run_morph_bundle(pairs, 3, out)
    table = check_summary_against_reports(out)
    assert len(table) == 3 and all(r["status"] == "ok" for r in table.values())


def test_a_pair_with_a_complete_report_is_skipped(pairs, tmp_path, capsys):
    out = tmp_path / "out"
    assert cli.main(["farm", "morph", str(pairs), "--index", "2", "-o", str(out)]) == 0
    report = out / "002_cube_to_cylinder" / "report.json"
    stamp = report.stat().st_mtime_ns
    assert cli.main(["farm", "morph", str(pairs), "--index", "2", "-o", str(out)]) == 0
    assert "complete already" in capsys.readouterr().out and report.stat().st_mtime_ns == stamp
    (out / "002_cube_to_cylinder" / "frames" / "frame_0001.obj").unlink()  # incomplete: made again
    assert cli.main(["farm", "morph", str(pairs), "--index", "2", "-o", str(out)]) == 0
    assert (out / "002_cube_to_cylinder" / "frames" / "frame_0001.obj").is_file()


def test_pair_lists_in_csv_and_their_errors(tmp_path, capsys):
    csv_path = tmp_path / "pairs.csv"
    elsewhere = tmp_path / "elsewhere" / "c.off"  # an absolute path stays as it is
    csv_path.write_text(f"source,target,frames,method\na.off,b.off,5,strip\n{elsewhere},d.off,,\n")
    got = morph_batch.read_pairs(csv_path)
    assert got[0] == {"name": "001_a_to_b", "source": str(tmp_path / "a.off"), "target": str(tmp_path / "b.off"),
                      "frames": 5, "method": "strip"}
    assert got[1]["source"] == str(elsewhere) and got[1]["frames"] == 8
    assert cli.main(["farm", "count", str(csv_path)]) == 0 and capsys.readouterr().out.strip() == "2"
    bad = tmp_path / "bad.json"
    for rows, message in (([{"source": "a.off"}], "pair 1: no target"),
                          ([{"source": "a", "target": "b", "method": "warp"}], "unknown method 'warp'"),
                          ([{"source": "a", "target": "b", "frames": "x"}], "frames must be a whole number"),
                          ([], "holds no pairs")):
        bad.write_text(json.dumps(rows))
        with pytest.raises(morph_batch.PairListError, match=message):
            morph_batch.read_pairs(bad)
    assert cli.main(["farm", "morph", str(csv_path), "--index", "3", "-o", str(tmp_path)]) == 2
    assert "--index 3 is outside the list's pairs 1..2" in capsys.readouterr().err


def test_a_pair_list_sets_the_field_methods_resolution_per_pair(tmp_path):
    """A `field_resolution` column sets the field method's lattice for its pair: the report's
    lattice_spacing is 1/N of the shapes' size and the summary names it. An empty cell is the
    default; a bad value, or one given to another method, fails the list before any morph."""
    am.write_mesh(tmp_path / "sphere.off", *shapes.icosphere(1))
    am.write_mesh(tmp_path / "cube.off", *shapes.cube())
    csv_path = tmp_path / "pairs.csv"
    csv_path.write_text("source,target,frames,method,field_resolution\n"
                        "sphere.off,cube.off,3,field,8\nsphere.off,cube.off,3,strip,\n")
    pairs = morph_batch.read_pairs(csv_path)
    assert pairs[0]["field_resolution"] == 8.0 and "field_resolution" not in pairs[1]
    out = tmp_path / "out"
    assert cli.main(["farm", "morph", str(csv_path), "--index", "1", "-o", str(out)]) == 0
    report = json.loads((out / pairs[0]["name"] / "report.json").read_text())
    assert report["status"] == "ok", report.get("error")
    assert report["validity"]["lattice_spacing"] == pytest.approx(1 / 8, rel=1e-12)
    assert morph_batch.summary_rows(pairs[:1], out)[0]["method"] == "field (8 cells)"
    bad = tmp_path / "bad.json"
    for row, message in (({"method": "strip", "field_resolution": 12}, "applies to the field method only, not 'strip'"),
                         ({"method": "field", "field_resolution": "fine"}, "lattice cells >= 2, got 'fine'"),
                         ({"method": "field", "field_resolution": 1}, "lattice cells >= 2, got 1"),
                         ({"method": "field", "field_resolution": True}, "lattice cells >= 2, got True")):
        bad.write_text(json.dumps([dict(row, source="a.off", target="b.off")]))
        with pytest.raises(morph_batch.PairListError, match=f"pair 1: field_resolution .*{message}"):
            morph_batch.read_pairs(bad)


def test_obj_and_ply_frames_carry_uvs_normals_and_materials(tmp_path):
    v, f = shapes.icosphere(1)
    uv = (v[:, :2] + 1) / 2
    materials = np.arange(len(f)) % 2
    obj = mesh_export.obj_bytes(v, f, uv, None, materials, ["Skin", "Cap"], "frame.mtl").decode()
    lines = obj.splitlines()
    assert "mtllib frame.mtl" in lines
    assert sum(ln.startswith("vt ") for ln in lines) == len(v)
    assert sum(ln.startswith("vn ") for ln in lines) == len(f)  # flat: one normal per face
    faces = [ln for ln in lines if ln.startswith("f ")]
    assert faces[0] == "f {0}/{0}/1 {1}/{1}/1 {2}/{2}/1".format(*(f[0] + 1))
    assert [ln for ln in lines if ln.startswith("usemtl")][:2] == ["usemtl Skin", "usemtl Cap"]
    (tmp_path / "a.obj").write_text(obj)
    ply = mesh_export.ply_bytes(v, f, uv, v, materials, ["Skin", "Cap"])
    (tmp_path / "a.ply").write_bytes(ply)
    for name in ("a.obj", "a.ply"):  # the core's reader still reads them
        rv, rf = am.read_mesh(tmp_path / name)
        np.testing.assert_allclose(rv, v, atol=1e-8)
        assert (rf == f).all()
    body = ply.decode().split("end_header\n")[1].splitlines()
    np.testing.assert_allclose(np.array(body[0].split(), float), np.concatenate([v[0], v[0], uv[0]]), atol=1e-8)
    assert body[len(v)].split() == ["3", *map(str, f[0]), "0"]
    with pytest.raises(ValueError, match="uv must be one row per vertex"):
        mesh_export.obj_bytes(v, f, uv[:-1])
    with pytest.raises(ValueError, match=r"faces index vertices 0\.\.41"):
        mesh_export.ply_bytes(v, f + 1)


def test_farm_frames_writes_each_integer_frame_once(tmp_path, capsys):
    frames = [shapes.icosphere(1)[0] * s for s in (1.0, 1.5, 1.2)]
    m = am.stitch(frames, shapes.icosphere(1)[1], [1.0, 5.0, 9.0])
    am.save(m, tmp_path / "walk.amf")
    assert cli.main(["farm", "frames", str(tmp_path / "walk.amf"), "--first", "0", "--last", "4",
                     "-o", str(tmp_path / "f"), "--format", "ply"]) == 0
    assert sorted(p.name for p in (tmp_path / "f").iterdir()) == [f"walk_{i:06d}.ply" for i in range(1, 5)]
    v, faces = am.read_mesh(tmp_path / "f" / "walk_000003.ply")
    s = m.slice(3.0)
    np.testing.assert_allclose(v[faces], s.vertices[s.faces], atol=1e-8)
    assert cli.main(["farm", "frames", str(tmp_path / "walk.amf"), "--first", "20", "--last", "30",
                     "-o", str(tmp_path / "f")]) == 2
    assert "frames 20–30 are outside" in capsys.readouterr().err
