"""``navcli run --live``: a viewer that connects late still gets the arena and the robot's body,
and the server's clock is the simulation's (a client of our own, speaking foxglove.sdk.v1)."""

from __future__ import annotations

import asyncio
import json
import os
import signal
import socket
import struct
import subprocess
import sys
import time

import pytest

from conftest import ROOT, SCENARIOS

websockets = pytest.importorskip("websockets")


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


async def _late_client(port: int, deadline: float) -> dict:
    """Connect, subscribe to /world/scene and /robot/body, and collect until both have arrived."""
    got: dict = {"topics": set(), "times": []}
    async with websockets.connect(f"ws://127.0.0.1:{port}", subprotocols=["foxglove.sdk.v1"], open_timeout=5) as ws:
        channels: dict[int, str] = {}
        subs: dict[int, str] = {}
        while time.monotonic() < deadline and not ({"/world/scene", "/robot/body"} <= got["topics"] and got["times"]):
            try:
                raw = await asyncio.wait_for(ws.recv(), timeout=max(0.1, deadline - time.monotonic()))
            except asyncio.TimeoutError:
                break
            if isinstance(raw, str):
                msg = json.loads(raw)
                if msg["op"] == "serverInfo":
                    got["capabilities"] = msg.get("capabilities", [])
                elif msg["op"] == "advertise":
                    for ch in msg["channels"]:
                        channels[ch["id"]] = ch["topic"]
                        if ch["topic"] in ("/world/scene", "/robot/body"):
                            sid = len(subs) + 1
                            subs[sid] = ch["topic"]
                            await ws.send(
                                json.dumps({"op": "subscribe", "subscriptions": [{"id": sid, "channelId": ch["id"]}]})
                            )
            elif raw[0] == 1:  # message data: subscription id, log time, payload
                sid, _ = struct.unpack_from("<IQ", raw, 1)
                got["topics"].add(subs[sid])
            elif raw[0] == 2:  # time: nanoseconds
                got["times"].append(struct.unpack_from("<Q", raw, 1)[0])
    return got


def test_a_late_viewer_gets_the_arena_the_robot_and_simulation_time(tmp_path):
    port = _free_port()
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    proc = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "navcli",
            "run",
            str(SCENARIOS / "paper-8x8.yaml"),
            "--live",
            "--port",
            str(port),
            "--time-limit",
            "30",
            "--out",
            str(tmp_path / "live.mcap"),
        ],
        env=env,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    try:
        t0 = time.monotonic()
        while time.monotonic() - t0 < 15:  # wait for the port to answer
            with socket.socket() as s:
                if s.connect_ex(("127.0.0.1", port)) == 0:
                    break
            time.sleep(0.1)
        time.sleep(1.5)  # join late: the first publications of the arena and body are gone
        got = asyncio.run(_late_client(port, time.monotonic() + 6))
    finally:
        proc.send_signal(signal.SIGTERM)
        try:
            code = proc.wait(timeout=15)
        except subprocess.TimeoutExpired:
            proc.kill()
            raise
    assert "time" in got.get("capabilities", [])
    assert {"/world/scene", "/robot/body"} <= got["topics"]
    # simulation time, in ns from the start: more than the 1.5 s joined late, far less than a wall clock
    assert got["times"] and 1.0e9 < got["times"][0] < 30e9
    assert code == 143 and (tmp_path / "live.mcap").exists()  # SIGTERM: 128 + 15


def test_after_the_mission_the_final_state_is_still_served_then_the_run_exits_with_its_outcome(tmp_path):
    """--linger: the mission ends (3 s, a timeout), its log is complete, and a viewer that joins
    afterwards still gets the arena, the robot's body and the time of the end; then navcli stops
    serving by itself and exits with the mission's code (3: not reached)."""
    from navcli.analysis import read_log

    port = _free_port()
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    log = tmp_path / "live.mcap"
    proc = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "navcli",
            "run",
            str(SCENARIOS / "paper-8x8.yaml"),
            "--live",
            "--port",
            str(port),
            "--time-limit",
            "3",
            "--linger",
            "6",
            "--out",
            str(log),
        ],
        env=env,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        t0 = time.monotonic()
        while not log.exists() and time.monotonic() - t0 < 30:  # the log gets its final name at the end
            time.sleep(0.1)
        assert log.exists() and proc.poll() is None  # ended, and still serving
        assert read_log(log).summary["outcome"] == "timeout"
        got = asyncio.run(_late_client(port, time.monotonic() + 4))
        code = proc.wait(timeout=20)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert {"/world/scene", "/robot/body"} <= got["topics"]
    assert got["times"] and abs(got["times"][-1] - 3.0e9) < 0.2e9  # the clock stays at the end
    err = proc.stderr.read()
    assert code == 3 and "still serving its final state" in err and "for 6 s" in err
