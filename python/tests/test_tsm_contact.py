"""The Python package against the CLI and against identities: the same histories as
`tsm-contact solve --json`, located scene errors, a callback and Ctrl-C that stop a run, the
independent audit that passes a true history and fails a falsified one, pickling, figures and
the Dask sweep on a local cluster."""

import json
import os
import pickle
import subprocess
import sys
import signal
import time
from pathlib import Path

import numpy as np
import pytest

import tsm_contact as tc

ROOT = Path(__file__).resolve().parents[2]


def cli():
    """The `tsm-contact` binary the test build made (or TSM_CONTACT_BIN)."""
    path = Path(os.environ.get("TSM_CONTACT_BIN", ROOT / "target" / "release" / "tsm-contact"))
    if not path.exists():
        pytest.fail(f"no tsm-contact binary at {path}: run ./test.sh (cargo test --release) first")
    return path


def without_seconds(h):
    """A history dict without the wall-clock times, which differ from run to run."""
    for r in h["increments"]:
        r.pop("seconds", None)
    return h


@pytest.mark.parametrize("name", tc.builtin_names())
def test_a_builtin_scene_gives_the_same_history_as_the_cli(name, tmp_path):
    out = tmp_path / "h.json"
    subprocess.run([str(cli()), "solve", name, "--json", str(out)], check=False, capture_output=True)
    want = without_seconds(json.loads(out.read_text()))
    got = without_seconds(json.loads(tc.solve(tc.Scene.builtin(name)).to_json()))
    assert got == want


def test_the_arrays_are_the_records(tmp_path):
    h = tc.solve(tc.Scene.builtin("example_3_2"), steps=30)
    assert h.positions.shape == (30, len(h.node_ids), 3)
    for k in (0, 12, 29):
        rec = h.record(k)
        assert np.array_equal(h.positions[k], np.array(rec["nodes"]))
        assert h.prescribed[k, 0] == rec["prescribed"][0]
        assert h.increments[k] == rec["increment"]
    c = h.contacts
    assert len(c["node"]) == sum(len(h.record(k)["contacts"]) for k in range(len(h)))
    assert set(c["body"]) <= {"A", "B", "C"}
    # The pin's driven displacement is the prescribed value: 0.01 m a step.
    assert np.allclose(h.prescribed[:, 0], -0.01 * h.increments, rtol=0, atol=1e-12)


def test_a_scene_file_with_a_bad_field_raises_with_the_field_and_the_line(tmp_path):
    text = tc.Scene.builtin("pin_on_cantilever").to_ron()
    lines = text.splitlines()
    k = next(i for i, l in enumerate(lines) if l.strip().startswith("E:"))
    lines[k] = lines[k].split("E:")[0] + "E: -1.0,"
    bad = tmp_path / "bad.ron"
    bad.write_text("\n".join(lines))
    with pytest.raises(tc.SceneError) as e:
        tc.Scene.from_file(bad)
    # The same file, line and field as the CLI names for the same file.
    assert e.value.field.startswith("sections[0].E")
    assert e.value.file == str(bad)
    assert e.value.line in range(1, k + 2)
    out = subprocess.run([str(cli()), "solve", str(bad)], capture_output=True, text=True)
    assert out.returncode != 0
    assert f"{bad}:{e.value.line}: {e.value.field}" in out.stderr
    assert isinstance(e.value, ValueError)


def test_a_dict_with_a_bad_value_raises_with_the_field():
    d = tc.Scene.builtin("example_3_2").to_dict()
    d["bodies"][1]["elements"] = 0
    with pytest.raises(tc.SceneError) as e:
        tc.Scene.from_dict(d)
    assert e.value.field.startswith("bodies[1].elements"), e.value.field
    d = tc.Scene.builtin("example_3_2").to_dict()
    d["bodies"][1]["elements"] = "ten"
    with pytest.raises(tc.SceneError) as e:
        tc.Scene.from_dict(d)
    assert e.value.field == "bodies[1].elements", e.value.field
    assert "line" not in e.value.message
    d = tc.Scene.builtin("example_3_2").to_dict()
    d["sectons"] = d.pop("sections")
    with pytest.raises(tc.SceneError) as e:
        tc.Scene.from_dict(d)
    assert "sectons" in str(e.value)


def test_a_scene_round_trips_through_ron_and_dict():
    s = tc.Scene.builtin("example_3_2_friction")
    a = tc.solve(s, steps=20)
    for t in (tc.Scene.from_text(s.to_ron()), tc.Scene.from_dict(s.to_dict()), pickle.loads(pickle.dumps(s))):
        assert np.array_equal(tc.solve(t, steps=20).positions, a.positions)


def test_the_callback_sees_every_increment_and_can_stop_the_run():
    seen = []

    def on_increment(r):
        seen.append(r["increment"])
        return r["increment"] < 7

    h = tc.solve(tc.Scene.builtin("example_3_2"), on_increment=on_increment)
    assert seen == list(range(1, 8))
    assert len(h) == 7
    assert not h.completed and "on_increment" in h.error


def test_an_exception_in_the_callback_is_raised():
    def on_increment(r):
        raise ZeroDivisionError("from the callback")

    with pytest.raises(ZeroDivisionError):
        tc.solve(tc.Scene.builtin("example_3_2"), on_increment=on_increment)


LONG_RUN = """
import sys
import tsm_contact as tc

scene = tc.Scene.from_text(
    '''(
    name: "long cantilever",
    sections: [(name: "s", E: 1.0, A: 1.0e4, I: 1.0)],
    bodies: [(name: "b", section: "s", path: [(0.0, 0.0), (1.0, 0.0)], elements: 400, first_node: 1)],
    supports: [(node: 1, u: true, v: true, phi: true)],
    loads: [(node: 401, fy: -0.01)],
    control: (steps: 1000000),
)'''
)
first = []


def on_increment(record):
    if not first:
        first.append(record)
        print("running", flush=True)


try:
    tc.solve(scene, on_increment=on_increment)
except KeyboardInterrupt:
    print("KeyboardInterrupt", flush=True)
    sys.exit(3)
print("finished", flush=True)
"""


def test_ctrl_c_stops_a_run_and_raises_keyboard_interrupt():
    # A real SIGINT to a Python process in a million-step solve (a minute and more): the run
    # stops at the next Newton iteration and KeyboardInterrupt reaches the caller.
    proc = subprocess.Popen(
        [sys.executable, "-c", LONG_RUN], stdout=subprocess.PIPE, text=True
    )
    try:
        assert proc.stdout.readline().strip() == "running"
        t0 = time.monotonic()
        proc.send_signal(signal.SIGINT)
        out, _ = proc.communicate(timeout=30)
    finally:
        proc.kill()
    assert out.strip() == "KeyboardInterrupt"
    assert proc.returncode == 3
    assert time.monotonic() - t0 < 10.0


def test_the_audit_passes_a_true_history_and_finds_a_node_moved_through_a_beam(tmp_path):
    h = tc.solve(tc.Scene.builtin("example_3_2"), steps=40)
    assert tc.check(h) == []
    d = json.loads(h.to_json())
    pin = d["node_ids"].index(34)
    k = 30
    d["increments"][k]["nodes"][pin][1] -= 0.2
    bad = tc.History.from_json(json.dumps(d))
    found = tc.check(bad)
    assert found and any(f["increment"] == d["increments"][k]["increment"] for f in found)


def test_a_history_saves_loads_and_pickles_to_the_same_history(tmp_path):
    h = tc.solve(tc.Scene.builtin("example_3_1"))
    path = tmp_path / "h.json"
    h.save(path)
    out = subprocess.run([str(cli()), "check", str(path)], capture_output=True, text=True)
    assert out.returncode == 0, out.stdout + out.stderr
    for g in (tc.History.load(path), pickle.loads(pickle.dumps(h))):
        assert np.array_equal(g.positions, h.positions)
        assert g.to_json() == h.to_json()


def test_figures_are_a_png_of_the_asked_size_and_an_svg_with_a_path_per_body(tmp_path):
    s = tc.Scene.builtin("example_3_2")
    h = tc.solve(s, steps=40)
    png = tmp_path / "f.png"
    tc.figure(h, 40, png, diagram="M", size=(640, 400))
    raw = png.read_bytes()
    assert raw[:8] == b"\x89PNG\r\n\x1a\n"
    assert int.from_bytes(raw[16:20], "big") == 640 and int.from_bytes(raw[20:24], "big") == 400
    svg = tmp_path / "f.svg"
    tc.figure(s, path=svg, steps=10)
    assert svg.read_text().count("<path id=") == 3
    with pytest.raises(ValueError):
        tc.figure(h, 40, tmp_path / "f.jpg")
    with pytest.raises(ValueError):
        tc.figure(tc.History.from_json(h.to_json()), 40, png)


def test_the_sweep_example_runs_on_a_local_cluster_of_two_workers(tmp_path):
    script = ROOT / "examples" / "python" / "sweep_friction.py"
    out = subprocess.run(
        [sys.executable, str(script), "--workers", "2", "--mu", "0", "0.3", "--step", "0.02", "--out", str(tmp_path)],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert out.returncode == 0, out.stderr[-2000:]
    rows = (tmp_path / "sweep_friction.csv").read_text().splitlines()
    assert len(rows) == 3
    assert (tmp_path / "sweep_friction.png").exists()
    # Friction holds the cantilevers back: the pin pushes harder with mu = 0.3 than without.
    force = {float(r.split(",")[0]): float(r.split(",")[4]) for r in rows[1:]}
    assert force[0.3] > force[0.0] > 0
