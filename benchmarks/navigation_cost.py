"""The Navigation system's wall time per tick (µs), for comparing two commits on one machine.

Times ``NavigationSystem.bid`` (its agents, the Map Manager, the Rescuer; not the Pilot, Vision or
physics) over four missions without a log: paper-8x8 (potential field, 300 s), landmarks-12
(60 s), blocked-wall (120 s, diverting targets) and u-trap (geometric, 120 s). It imports
``navcli`` from the current directory, so run it from each checkout in turn, alternating, and
compare medians:

    git worktree add /tmp/old <commit>
    for i in 1 2 3; do (cd /tmp/old && python $PWD/benchmarks/navigation_cost.py); python benchmarks/navigation_cost.py; done

Each line gives ``scenario:µs/ticks``; the tick counts say whether the two commits ran the same
missions (the cost of different paths is not the same work).
"""

from __future__ import annotations

import sys
import time

sys.path.insert(0, ".")  # the checkout this is run from, not the installed package

from navcli.config import RunSpec  # noqa: E402
from navcli.mission import Mission  # noqa: E402
from navcli.navigation import NavigationSystem  # noqa: E402
from navcli.scenario import load_scenario  # noqa: E402

MISSIONS = (
    ("paper-8x8", "potential-field", 300.0),
    ("landmarks-12", "potential-field", 60.0),
    ("blocked-wall", "potential-field", 120.0),
    ("u-trap", "geometric", 120.0),
)


def main() -> None:
    spent = [0.0]
    bid = NavigationSystem.bid

    def timed(self, beliefs):
        t = time.perf_counter()
        out = bid(self, beliefs)
        spent[0] += time.perf_counter() - t
        return out

    NavigationSystem.bid = timed  # type: ignore[method-assign]
    costs = []
    for name, pilot, limit in MISSIONS:
        m = Mission(
            RunSpec.build(load_scenario(f"scenarios/{name}.yaml"), pilot=pilot, time_limit=limit), snapshots=False
        )
        spent[0] = 0.0
        while m.outcome is None:
            m.step()
        costs.append(f"{name}:{spent[0] / m.ticks * 1e6:.1f}us/{m.ticks}")
    print(" ".join(costs))


if __name__ == "__main__":
    main()
