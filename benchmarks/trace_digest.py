"""A digest of 20 missions' logs, for refactors that must not change behaviour.

Runs 10 bundled scenarios x both pilots (seed 1, at most 120 simulated s each: about 8 s in all),
and prints, per mission, a sha256 of every topic's raw messages with their log times. Run it
before and after a change and compare the two outputs: equal digests mean every message of
every log is byte-identical.

    python benchmarks/trace_digest.py > before.json   # then, after the change:
    python benchmarks/trace_digest.py > after.json && cmp before.json after.json
"""

from __future__ import annotations

import hashlib
import json
import sys
import tempfile
from pathlib import Path

from mcap.reader import make_reader

from navcli import RunSpec, load_scenario, run_mission

SCENARIOS = Path(__file__).resolve().parents[1] / "scenarios"
NAMES = (
    "paper-8x8",
    "landmarks-12",
    "open-arena",
    "slanted-8x8",
    "blocked-wall",
    "door-wall",
    "hidden-fence",
    "river-bridges",
    "u-trap",
    "trap-box",
)


def digest(log: Path) -> dict[str, str]:
    topics: dict[str, hashlib._Hash] = {}
    with log.open("rb") as f:
        for _, channel, message in make_reader(f).iter_messages(log_time_order=True):
            h = topics.setdefault(channel.topic, hashlib.sha256())
            h.update(message.log_time.to_bytes(8, "little"))
            h.update(message.data)
    return {t: h.hexdigest()[:16] for t, h in sorted(topics.items())}


def main() -> None:
    out = {}
    with tempfile.TemporaryDirectory() as tmp:
        for name in NAMES:
            sc = load_scenario(SCENARIOS / f"{name}.yaml")
            for pilot in ("potential-field", "geometric"):
                spec = RunSpec.build(sc, pilot=pilot, seed=1, time_limit=min(sc.mission.time_limit, 120.0))
                log = Path(tmp) / f"{name}-{pilot}.mcap"
                r = run_mission(spec, out=log)
                out[f"{name}/{pilot}"] = digest(log)
                print(f"{name} {pilot}: {r.summary['outcome']} after {r.summary['ticks']} ticks", file=sys.stderr)
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
