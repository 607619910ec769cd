"""Gymnasium's own checks on hadal.env, where Gymnasium is importable (it is not a Debian 12 package, so the
default test run skips this; the issue notes record a run against Gymnasium's source)."""

import pytest

gymnasium = pytest.importorskip("gymnasium")
from gymnasium.utils.env_checker import check_env  # noqa: E402

import hadal.env  # noqa: E402


@pytest.mark.parametrize("task", ["waypoint", "station_keeping"])
def test_check_env_passes(task):
    with hadal.env.HadalEnv(task=task, seed=1) as env:
        assert isinstance(env, gymnasium.Env) and isinstance(env.observation_space, gymnasium.spaces.Box)
        check_env(env, skip_render_check=True)


@pytest.mark.parametrize("env_id", ["Hadal/WaypointAtDepth-v0", "Hadal/StationKeeping-v0"])
def test_registered_ids_make_working_envs(env_id):
    env = gymnasium.make(env_id)
    try:
        observation, _ = env.reset(seed=3)
        assert env.observation_space.contains(observation)
        observation, reward, terminated, truncated, _ = env.step(env.action_space.sample())
        assert env.observation_space.contains(observation) and isinstance(reward, float)
    finally:
        env.close()
