"""Model files are inputs like scenarios: every damaged or foreign ``.npz`` is refused in one
sentence (exit 2 from the command line), never half-used, never a traceback; and a training never
writes over a file that is not its own."""

from __future__ import annotations

import io
import json
import zipfile
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from conftest import SCENARIOS
from navcli.cli import app
from navcli.learning import model_file
from navcli.learning.actions import ACTIONS
from navcli.learning.features import N_STATES

ROOM = SCENARIOS / "landmarks-12.yaml"


def _arrays() -> tuple[dict[str, np.ndarray], dict]:
    with np.load(model_file.BUNDLED, allow_pickle=False) as z:
        arrays = {k: z[k] for k in z.files}
    return arrays, json.loads(str(arrays.pop("meta")))


def _write(path: Path, arrays: dict, meta) -> Path:
    np.savez(path, meta=np.array(json.dumps(meta)), **arrays)
    return path


def _changed(**changes):
    """A maker of the bundled model with ``changes`` (name: array, or None to drop it)."""

    def make(path: Path) -> Path:
        arrays, meta = _arrays()
        for k, v in changes.items():
            if v is None:
                arrays.pop(k)
            else:
                arrays[k] = v(arrays[k]) if callable(v) else v
        return _write(path, arrays, meta)

    return make


def _meta(m):
    def make(path: Path) -> Path:
        arrays, meta = _arrays()
        return _write(path, arrays, m(meta) if callable(m) else m)

    return make


def _bytes(f):
    def make(path: Path) -> Path:
        path.write_bytes(f(model_file.BUNDLED.read_bytes()))
        return path

    return make


def _flip(data: bytes) -> bytes:
    b = bytearray(data)
    b[len(b) // 2] ^= 0xFF  # inside a compressed array: its CRC no longer holds
    return bytes(b)


def _bomb(path: Path) -> Path:
    """An archive whose one member claims to unpack beyond the bound (written with the claim only)."""
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr("policy.npy", b"\0" * (model_file.MAX_BYTES + 1))
    return path


BAD = {
    "empty": (lambda p: (p.write_bytes(b""), p)[1], "empty"),
    "truncated": (_bytes(lambda d: d[: len(d) // 2]), "not an .npz archive"),
    "a flipped byte": (_bytes(_flip), "damaged"),
    "text": (lambda p: (p.write_text("policy: all-MB\n"), p)[1], "not an .npz archive"),
    "a zip bomb": (_bomb, "unpack beyond"),
    "no meta": (lambda p: (np.savez(p, **_arrays()[0]), p)[1], "no metadata"),
    "meta a JSON list": (_meta([1, 2]), "not a JSON object"),
    "meta not JSON": (lambda p: (np.savez(p, meta=np.array("{nope"), **_arrays()[0]), p)[1], "not JSON"),
    "unknown algorithm": (_meta(lambda m: {**m, "algorithm": "sarsa"}), "no known algorithm"),
    "trials negative": (_meta(lambda m: {**m, "trials": -1}), "'trials'"),
    "seed a string": (_meta(lambda m: {**m, "seed": "1"}), "'seed'"),
    "policy missing": (_changed(policy=None), "'policy' is missing"),
    "policy too short": (_changed(policy=lambda a: a[:-1]), "has shape"),
    "policy of floats": (_changed(policy=lambda a: a.astype(float)), "not integers"),
    "policy out of range": (_changed(policy=lambda a: np.full_like(a, len(ACTIONS))), "outside"),
    "values NaN": (_changed(values=lambda a: np.where(np.arange(a.size) == 3, np.nan, a)), "NaN"),
    "values infinite": (_changed(values=lambda a: np.full_like(a, np.inf)), "NaN or infinite"),
    "counts of another length": (_changed(count_value=lambda a: a[:-1]), "differ in length"),
    "count index beyond the states": (
        _changed(count_index=lambda a: np.where(np.arange(a.shape[1]) == 0, N_STATES, a)),
        "does not exist",
    ),
    "steps an array": (_changed(steps=np.arange(3)), "has shape"),
    "an array too many": (_changed(extra=np.zeros(2)), "does not"),
}


@pytest.mark.parametrize("case", BAD, ids=str)
def test_a_bad_model_file_is_refused_in_one_sentence(tmp_path, case):
    make, words = BAD[case]
    path = make(tmp_path / "m.npz")
    with pytest.raises(model_file.ModelError) as e:
        model_file.load(path)
    assert str(path) in str(e.value) and words in str(e.value), str(e.value)


def test_the_bundled_model_and_a_folder(tmp_path):
    arrays, meta = model_file.load(model_file.BUNDLED)
    assert meta["algorithm"] in ("prioritized-sweeping", "q-learning") and arrays["policy"].shape == (N_STATES,)
    with pytest.raises(model_file.ModelError, match="is a folder"):
        model_file.load(tmp_path)
    with pytest.raises(model_file.ModelError, match="no such model file"):
        model_file.load(tmp_path / "nope.npz")


def test_a_model_larger_than_the_bound_is_refused_unread(tmp_path, monkeypatch):
    monkeypatch.setattr(model_file, "MAX_BYTES", model_file.BUNDLED.stat().st_size - 1)
    with pytest.raises(model_file.ModelError, match="larger than a model can be"):
        model_file.load(model_file.BUNDLED)


def _declaring(path: Path, shape: tuple[int, ...]) -> Path:
    """The bundled model with its ``values`` array's header declaring ``shape`` (64 bytes of data)."""
    with zipfile.ZipFile(model_file.BUNDLED) as z:
        members = {n: z.read(n) for n in z.namelist()}
    head = io.BytesIO()
    np.lib.format.write_array_header_1_0(head, {"descr": "<f8", "fortran_order": False, "shape": shape})
    members["values.npy"] = head.getvalue() + bytes(64)  # (the header writer writes the magic too)
    with zipfile.ZipFile(path, "w") as z:
        for n, data in members.items():
            z.writestr(n, data)
    return path


def test_an_array_declared_too_large_is_refused_before_it_is_allocated(tmp_path):
    """A header may declare any shape: 10^11 floats (745 GiB) must be refused from the header alone."""
    with pytest.raises(model_file.ModelError, match="declares"):
        model_file.load(_declaring(tmp_path / "m.npz", (10**11,)))


def test_what_is_not_a_regular_file_is_refused_unread(tmp_path):
    import os

    fifo = tmp_path / "f.npz"
    os.mkfifo(fifo)  # opening it would wait for a writer for ever
    zero = tmp_path / "z.npz"
    zero.symlink_to("/dev/zero")  # reading it would never end
    loop = tmp_path / "l.npz"
    loop.symlink_to(loop)
    for path, words in ((fifo, "not a regular file"), (zero, "not a regular file"), (loop, "cannot be read")):
        with pytest.raises(model_file.ModelError, match=words):
            model_file.load(path)


@pytest.mark.parametrize(
    "case", ["empty", "truncated", "a flipped byte", "meta a JSON list", "policy of floats", "values NaN"]
)
@pytest.mark.parametrize("command", ["run", "compare policies", "train --resume"])
def test_every_command_that_reads_a_model_refuses_it_with_exit_2(tmp_path, case, command):
    path = BAD[case][0](tmp_path / "m.npz")
    before = sorted(tmp_path.iterdir())
    args = {
        "run": ["run", str(ROOM), "--navigation", f"learned:{path}", "--out", str(tmp_path / "r.mcap")],
        "compare policies": [
            "compare",
            "policies",
            str(ROOM),
            "--policy",
            f"learned:{path}",
            "--runs",
            "1",
            "--starts",
            "1",
            "--jobs",
            "1",
            "--out",
            str(tmp_path / "cmp"),
        ],
        "train --resume": ["train", str(ROOM), "--resume", str(path), "--trials", "1", "--jobs", "1"],
    }[command]
    r = CliRunner().invoke(app, args)
    assert r.exit_code == 2, r.output
    assert "Traceback" not in r.output and str(path) in r.output and BAD[case][1] in r.output
    assert sorted(tmp_path.iterdir()) == before  # nothing written


@pytest.mark.parametrize(
    "out, words",
    [
        ("scenario.yaml", "give a name ending in .npz"),  # a name that would overwrite the scenario itself
        ("folder", "is a folder"),
        ("folder/", "is a folder"),
        ("dev.npz", "not a regular file"),  # a link to the device /dev/full: a device is never replaced
        ("m.npz/x.npz", "is a file, not a folder"),
    ],
)
def test_train_never_writes_over_what_it_did_not_write(tmp_path, out, words):
    scenario = tmp_path / "scenario.yaml"
    scenario.write_bytes(ROOM.read_bytes())
    (tmp_path / "folder").mkdir()
    (tmp_path / "m.npz").write_bytes(b"")
    if out == "dev.npz":
        if not Path("/dev/full").exists():
            pytest.skip("no /dev/full here")
        (tmp_path / out).symlink_to("/dev/full")
    before = sorted(tmp_path.iterdir())
    r = CliRunner().invoke(
        app,
        [
            "train",
            str(scenario),
            "--trials",
            "1",
            "--eval-every",
            "1",
            "--eval-starts",
            "1",
            "--jobs",
            "1",
            "--out",
            f"{tmp_path}/{out}",
        ],
    )
    assert r.exit_code == 2 and words in r.output and "Traceback" not in r.output, r.output
    assert scenario.read_bytes() == ROOM.read_bytes() and sorted(tmp_path.iterdir()) == before


def test_train_refuses_a_side_file_of_another_kind(tmp_path):
    """``--out m.npz`` writes m-curve.png beside it: a file of that name that is not a PNG stays."""
    png = tmp_path / "m-curve.png"
    png.write_text("my notes\n")
    r = CliRunner().invoke(app, ["train", str(ROOM), "--trials", "1", "--jobs", "1", "--out", str(tmp_path / "m.npz")])
    assert r.exit_code == 2 and "m-curve.png" in r.output and "not a .png file navcli writes" in r.output
    assert png.read_text() == "my notes\n" and not (tmp_path / "m.npz").exists()


def test_a_save_leaves_no_temporary_file_and_replaces_its_own_model(tmp_path):
    from navcli import RunSpec, load_scenario
    from navcli.training.trainer import make_learner

    spec = RunSpec.build(load_scenario(ROOM))
    out = tmp_path / "m.npz"
    for trials in (1, 2):
        model_file.save(
            out, make_learner("q-learning", spec, 1), {"algorithm": "q-learning", "seed": 1, "trials": trials}
        )
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m.json", "m.npz"]
    assert model_file.load(out)[1]["trials"] == 2 and json.loads((tmp_path / "m.json").read_text())["trials"] == 2
    assert io.BytesIO(out.read_bytes()).read(4) == b"PK\x03\x04"


def test_an_encrypted_member_is_refused_in_one_sentence(tmp_path):
    """A zip member with the encryption flag set (zipfile would ask for a password, a RuntimeError)."""
    path = tmp_path / "enc.npz"
    data = bytearray(model_file.BUNDLED.read_bytes())
    data[6] |= 0x1  # the first local header's general-purpose flags: encrypted
    cd = data.rfind(b"PK\x01\x02")
    while cd >= 0:  # and every central-directory entry's
        data[cd + 8] |= 0x1
        cd = data.rfind(b"PK\x01\x02", 0, cd)
    path.write_bytes(bytes(data))
    with pytest.raises(model_file.ModelError, match="encrypted|damaged"):
        model_file.load(path)
