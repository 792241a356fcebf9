"""navcli's learners beyond the learning paper: the sampled policies (softmax over the learned
model's action values, the PPO agent's table), their plugins in ``compare policies`` and
``plugins list``, the temperature's choice on training rooms, and ``train-rl`` (Stable-Baselines3:
its tests skip where the optional extra ``navcli[rl]`` is not installed)."""

from __future__ import annotations

import hashlib
import json
import math
import zipfile

import numpy as np
import pytest
from typer.testing import CliRunner

from navcli.cli import app
from navcli.learning import model_file
from navcli.learning.actions import ACTIONS
from navcli.learning.features import N_STATES
from navcli.learning.ppo import BUNDLED_PPO, PPOParams, PPOPolicy, load_table
from navcli.learning.sampled import SAMPLE_STREAM, check_probabilities, sampler, trial_sampler
from navcli.learning.softmax import CHOICE, SoftmaxParams, SoftmaxPolicy, action_values, softmax

A = len(ACTIONS)
HELD_OUT = {
    "drawn-8x8-a",
    "drawn-8x8-b",
    "drawn-door",
    "scattered-8x8",
    "crossed-8x8",
    "landmarks-drawn",
    "landmarks-drawn-b",
}


def _bundled_q() -> np.ndarray:
    arrays, meta = model_file.load(model_file.BUNDLED)
    return action_values(arrays, meta)


def test_softmax_at_zero_temperature_is_the_learned_greedy_policy_and_unknown_states_draw_uniformly():
    q = _bundled_q()
    visited = np.isfinite(q).any(axis=1)
    p = softmax(q, 0.0)
    greedy = model_file.load_policy()
    assert visited.sum() > 100  # the bundled model knows a few hundred states
    assert (p[visited].argmax(axis=1) == greedy[visited]).all()
    assert (p[visited].max(axis=1) == 1.0).all()
    assert np.allclose(p[~visited], 1 / A)


def test_softmax_weights_actions_by_their_values_and_never_draws_an_untried_one():
    q = np.full((N_STATES, A), -np.inf)
    q[0, :3] = [-10.0, -12.0, -10.0 - 2 * math.log(3)]  # at T = 2: weights 1, e^-1, 1/3
    p = softmax(q, 2.0)
    w = np.array([1.0, math.exp(-1.0), 1 / 3])
    assert np.allclose(p[0, :3], w / w.sum()) and (p[0, 3:] == 0).all()
    hot = softmax(q, 1e6)  # very hot: uniform over the three tried actions
    assert np.allclose(hot[0, :3], 1 / 3, atol=1e-5) and (hot[0, 3:] == 0).all()


def test_the_sampler_draws_each_action_as_often_as_its_probability_and_repeats_with_its_seed():
    p = np.zeros((N_STATES, A))
    p[:, 1], p[:, 4] = 0.25, 0.75
    draws = [sampler(p, np.random.default_rng(5))(7) for _ in range(1)]
    choose = sampler(p, np.random.default_rng(5))
    many = np.array([choose(7) for _ in range(4000)])
    assert set(many) == {1, 4}
    # 4000 draws of 0.25: standard deviation sqrt(4000 * 0.25 * 0.75) = 27.4; 5 of them is 137
    assert abs((many == 1).sum() - 1000) < 137
    again = sampler(p, np.random.default_rng(5))
    assert [again(7) for _ in range(50)] == list(many[:50]) and draws[0] == many[0]
    # a trial's stream is its start's seed and SAMPLE_STREAM, apart from the random policy's
    t = trial_sampler(p, 123)
    ref = sampler(p, np.random.default_rng([123, SAMPLE_STREAM]))
    assert [t(0) for _ in range(20)] == [ref(0) for _ in range(20)]


def test_a_table_that_is_not_probabilities_is_refused():
    bad = np.full((N_STATES, A), 0.3)
    with pytest.raises(ValueError, match="sum to 1"):
        check_probabilities(bad)
    with pytest.raises(ValueError, match="shape"):
        check_probabilities(np.full((3, A), 0.2))


def test_the_bundled_temperature_was_chosen_on_training_rooms_by_its_rule():
    choice = json.loads(CHOICE.read_text())
    assert set(choice["rooms"]) and not set(choice["rooms"]) & HELD_OUT
    rows = choice["grid"]
    best = max(rows, key=lambda r: (r["reward"], -r["temperature"]))
    assert choice["temperature"] == best["temperature"] == SoftmaxParams().temperature
    assert all(r["trials"] == choice["starts_per_room"] * len(choice["rooms"]) for r in rows)
    # made for the bundled model: a model trained again needs `navcli tune-softmax` again
    assert choice["model_sha256"] == hashlib.sha256(model_file.BUNDLED.read_bytes()).hexdigest()


def test_the_temperature_rule_takes_the_best_mean_reward_and_the_lowest_temperature_on_a_tie(monkeypatch):
    import navcli.rl.temperature as temperature
    from navcli.scenario import load_scenario
    from navcli.training.task import task_spec

    rewards = {1.0: [-30.0, -50.0], 2.0: [-20.0, -60.0], 4.0: [-10.0, -70.0], 8.0: [-90.0, -90.0]}
    monkeypatch.setattr(
        temperature,
        "run_job",
        lambda job: [{"outcome": "reached", "reward": r, "actions": 1} for r in rewards[job.temperature]],
    )
    spec = task_spec(load_scenario("landmarks-12"))
    choice = temperature.choose([spec], tuple(rewards), starts=2)
    # means -40, -40, -40, -90: a three-way tie, the lowest temperature wins
    assert choice["temperature"] == 1.0
    assert [r["reward"] for r in choice["grid"]] == [-40.0, -40.0, -40.0, -90.0]
    rewards[4.0] = [-10.0, -60.0]  # -35: the best
    assert temperature.choose([spec], tuple(rewards), starts=2)["temperature"] == 4.0


def test_the_ppo_plugin_draws_from_the_bundled_table_or_takes_its_most_probable_action():
    p, meta = load_table()
    arrays, _ = model_file.load(BUNDLED_PPO)
    assert meta["algorithm"] == "sb3" and meta["agent"] == "ppo" and meta["scenario"] == "landmarks-12"
    assert np.allclose(PPOPolicy.probabilities(), p) and np.allclose(p.sum(axis=1), 1.0)
    greedy = PPOPolicy.probabilities(PPOParams(sample=False))
    assert (greedy.argmax(axis=1) == arrays["policy"]).all() and (greedy.max(axis=1) == 1.0).all()
    assert (model_file.load_policy(BUNDLED_PPO) == arrays["policy"]).all()  # learned:FILE runs it greedily


def test_a_model_file_whose_probabilities_do_not_sum_to_one_is_refused(tmp_path):
    class Table:
        algorithm = "sb3"

        def to_arrays(self):
            p = np.full((N_STATES, A), 0.2)
            p[3] = [0.5, 0.5, 0.5, 0.0, 0.0]
            return {"probabilities": p, "policy": p.argmax(axis=1).astype(np.int8), "steps": np.array(1)}

    path = model_file.save(tmp_path / "bad.npz", Table(), {"seed": 1, "trials": 1})
    with pytest.raises(model_file.ModelError, match="do not sum to 1"):
        model_file.load(path)


def test_plugins_list_lists_the_sampled_policies_with_their_parameters():
    r = CliRunner().invoke(app, ["plugins", "list"])
    assert r.exit_code == 0, r.output
    lines = {line.split()[1]: line for line in r.output.splitlines() if line.startswith("policy")}
    assert "softmax.temperature" in lines["softmax"] and "ppo.sample" in lines["ppo"]


def test_compare_runs_a_sampled_policy_as_trials_of_actions_with_their_reward(tmp_path):
    from navcli.scenario import load_scenario
    from navcli.training.comparison import job_key, parse_policy, plan, run_trials
    from navcli.training.task import task_spec

    spec = task_spec(load_scenario("landmarks-12"), {"learning.max_actions": 6})
    soft, rand = parse_policy("softmax"), parse_policy("random")
    assert soft.kind == "sampled" and "temperature" in soft.about and soft.table is None
    job = plan(spec, [soft], 1, 2, tmp_path)[0]
    first, again = run_trials(job), run_trials(job)
    assert first == again  # the same trial draws the same actions
    for t in first:
        counts = [t[a] for a in ACTIONS]
        assert sum(counts) == t["actions"] <= 6
        assert t["reward"] == sum(c * r for c, r in zip(counts, (-1, -10, -6, -5, -5)))
    mb = np.zeros((N_STATES, A))
    mb[:, 0] = 1.0  # a table that draws MB everywhere: its trials take MB alone
    only_mb = type(soft)("softmax", "sampled", None, "MB", probabilities=mb.tobytes())
    for t in run_trials(plan(spec, [only_mb], 1, 2, tmp_path)[0]):
        assert t["MB"] == t["actions"] > 0 and t["reward"] == -t["actions"]
    other = SoftmaxPolicy.probabilities(SoftmaxParams(temperature=SoftmaxParams().temperature * 2 + 1))
    hotter = type(soft)(soft.label, soft.kind, None, soft.about, probabilities=other.tobytes())
    assert job_key(spec, hotter, 0, job.starts) != job.key != job_key(spec, rand, 0, job.starts)


def test_an_sb3_archive_is_one_navcli_replaces_and_a_foreign_zip_is_not(tmp_path):
    from navcli.outputs import navcli_wrote

    ours, theirs = tmp_path / "a.zip", tmp_path / "b.zip"
    with zipfile.ZipFile(ours, "w") as z:
        z.writestr("data", "{}")
        z.writestr("_stable_baselines3_version", "2.9.2")
    with zipfile.ZipFile(theirs, "w") as z:
        z.writestr("data", "{}")
    assert navcli_wrote(ours) and not navcli_wrote(theirs)


def test_stable_baselines3_is_found_in_the_rl_extra():
    from navcli.checks.extras import extra_of

    assert extra_of("stable_baselines3") == extra_of("stable-baselines3") == extra_of("torch") == "rl"


# --- Stable-Baselines3 itself: only where navcli[rl] is installed -----------------------------------
def _sb3():
    return pytest.importorskip("stable_baselines3", reason="navcli[rl] (Stable-Baselines3, torch) is not installed")


def test_train_rl_writes_the_agents_table_the_archive_and_repeats_with_its_seed(tmp_path):
    sb3 = _sb3()
    from navcli.rl.sb3 import policy_table

    outs = []
    for name in ("a", "b"):
        out = tmp_path / f"{name}.npz"
        r = CliRunner().invoke(app, ["train-rl", "landmarks-12", "--agent", "dqn", "--steps", "150", "--out", str(out)])
        assert r.exit_code == 0, r.output
        outs.append(out)
    (a, meta), (b, _) = model_file.load(outs[0]), model_file.load(outs[1])
    assert meta["algorithm"] == "sb3" and meta["agent"] == "dqn" and meta["steps_trained"] == 150
    assert np.array_equal(a["probabilities"], b["probabilities"])  # the same seed, the same agent
    model = sb3.DQN.load(outs[0].with_suffix(".zip"), device="cpu")
    assert np.array_equal(policy_table(model, "dqn").argmax(axis=1), a["policy"])


def test_the_ppo_table_is_the_networks_policy(tmp_path):
    sb3 = _sb3()
    from navcli.rl.sb3 import policy_table

    out = tmp_path / "ppo.npz"
    r = CliRunner().invoke(app, ["train-rl", "landmarks-12", "--steps", "64", "--seed", "3", "--out", str(out)])
    assert r.exit_code == 0, r.output
    arrays, _ = model_file.load(out)
    model = sb3.PPO.load(out.with_suffix(".zip"), device="cpu")
    table = policy_table(model, "ppo")
    assert np.allclose(arrays["probabilities"], table, atol=1e-6)
    obs = np.array([5, 400, 979])
    for s in obs:  # the library's own distribution of the state, as the table says
        dist = model.policy.get_distribution(model.policy.obs_to_tensor(np.array([s]))[0])
        assert np.allclose(dist.distribution.probs.detach().numpy()[0], table[s], atol=1e-6)
