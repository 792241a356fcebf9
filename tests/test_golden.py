"""Golden-log tests: a compact digest of the bundled paper-8x8 mission, per pilot.

The digest (tests/golden/*.json) is small and reviewable: the summary, who won the motion
resource how often, the events, and the pose every 5 simulated seconds. A change of behaviour
shows up as a diff of it. Refresh deliberately with ``pytest --update-goldens`` and review the diff.
"""

from __future__ import annotations

import json
from collections import Counter

import pytest

from navcli.analysis import path_length, read_log
from conftest import ROOT, SCENARIOS
from navcli.config import RunSpec
from navcli.runner import run_mission
from navcli.scenario import load_scenario

GOLDEN = ROOT / "tests" / "golden"
SAMPLE_EVERY = 50  # ticks


def digest(log) -> dict:
    s = log.summary
    poses = log["/robot/pose"]
    sample = poses.iloc[::SAMPLE_EVERY]
    return {
        "summary": {k: s[k] for k in ("scenario", "seed", "pilot", "outcome", "ticks", "collisions", "camera_looks")}
        | {"time_s": round(s["time_s"], 3), "path_length_m": round(s["path_length_m"], 3)},
        "motion_winners": dict(sorted(Counter(log["/bids"]["motion.winner"].fillna("none")).items())),
        "events": [
            f"{t:.1f} {n}: {m}" for t, n, m in log["/events"][["time_s", "name", "message"]].itertuples(index=False)
        ],
        "poses": [
            [round(t, 1), round(x, 3), round(y, 3), round(th, 3)]
            for t, x, y, th in sample[["time_s", "x", "y", "theta"]].itertuples(index=False)
        ],
    }


def _dump(d: dict) -> str:
    """JSON with one pose per line, so a diff of a golden file reads as a diff of the path."""
    head = json.dumps({k: v for k, v in d.items() if k != "poses"}, indent=1)[:-2]
    rows = ",\n  ".join(json.dumps(p) for p in d["poses"])
    return f'{head},\n "poses": [\n  {rows}\n ]\n}}\n'


@pytest.mark.parametrize("slip", [None, 0.0], ids=["default", "slip-0"])
@pytest.mark.parametrize("pilot", ["potential-field", "geometric"])
def test_paper_8x8_matches_its_golden_digest(pilot, slip, tmp_path, request):
    """The bundled mission as it runs, and with the wheels' slip off (``robot.slip_noise`` 0): the
    second digest is the one of the deterministic drive, which the switch must give back exactly."""
    sc = load_scenario(SCENARIOS / "paper-8x8.yaml")
    out = tmp_path / f"{pilot}.mcap"
    overrides = {} if slip is None else {"robot.slip_noise": slip}
    run_mission(RunSpec.build(sc, pilot=pilot, seed=1, overrides=overrides), out=out)
    log = read_log(out)
    got = digest(log)
    assert log.summary["path_length_m"] == pytest.approx(path_length(log["/robot/pose"]), rel=0.01)
    path = GOLDEN / f"paper-8x8-{pilot}{'' if slip is None else '-slip-0'}.json"
    if request.config.getoption("--update-goldens"):
        path.write_text(_dump(got))
        pytest.skip(f"rewrote {path.name}")
    assert path.exists(), f"no golden digest {path.name}: run pytest --update-goldens and review it"
    want = json.loads(path.read_text())
    assert got["summary"] | {"time_s": 0, "path_length_m": 0} == want["summary"] | {"time_s": 0, "path_length_m": 0}
    assert got["summary"]["time_s"] == pytest.approx(want["summary"]["time_s"], abs=1e-6)
    assert got["summary"]["path_length_m"] == pytest.approx(want["summary"]["path_length_m"], abs=2e-3)
    assert got["motion_winners"] == want["motion_winners"]
    assert got["events"] == want["events"]
    assert len(got["poses"]) == len(want["poses"])
    for g, w in zip(got["poses"], want["poses"]):
        assert g == pytest.approx(w, abs=2e-3), f"pose at t = {w[0]} s"
