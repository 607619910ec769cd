"""hadal.env.DaskVectorEnv on a real Dask LocalCluster: the envs live in worker processes (Dask actors, a
VectorEnv of lockstep hadalds each) and give what the local VectorEnv gives, to the bit."""

import numpy as np
import pytest

import hadal.env
from hadal.cluster import SchedulerUnreachable


def assert_same_step(a, b):
    for x, y in zip(a[:4], b[:4]):
        assert np.array_equal(x, y)
    for info_a, info_b in zip(a[4], b[4]):
        assert info_a.keys() == info_b.keys()
        for key in ("final_observation", "sim_time", "episode_step"):
            if key in info_a:
                assert np.array_equal(info_a[key], info_b[key]), key


def test_envs_on_dask_workers_step_as_the_local_vector_env_to_the_bit():
    """Four envs, two on each of two worker processes, against VectorEnv(4) with the same seeds and actions:
    the same observations, rewards and episode ends (episodes of 4 steps: an autoreset each), by step() and
    by step_many() (several steps in one round trip)."""
    with hadal.env.DaskVectorEnv(4, envs_per_worker=2, task="waypoint", seed=7, max_episode_steps=4) as remote, \
            hadal.env.VectorEnv(4, task="waypoint", seed=7, max_episode_steps=4, pin_cpus=False) as local:
        assert [count for _, count, _ in remote.groups] == [2, 2] and len({w for _, _, w in remote.groups}) == 2
        assert remote.action_space.shape == local.action_space.shape == (4, 3)
        assert remote.observation_space.shape == local.observation_space.shape
        # Seeded at construction (env i: seed + i), not by the reset.
        observation_remote, infos_remote = remote.reset()
        observation_local, infos_local = local.reset()
        assert np.array_equal(observation_remote, observation_local)
        assert [i["noise_seed"] for i in infos_remote] == [i["noise_seed"] for i in infos_local]
        rng = np.random.default_rng(3)
        ended = 0
        for _ in range(6):
            actions = rng.uniform(-1.0, 1.0, size=(4, 3))
            a, b = remote.step(actions), local.step(actions)
            assert_same_step(a, b)
            ended += int(np.sum(a[3]))
        assert ended == 4  # every env's 4-step episode ended once, and was reset in the same call
        sequence = rng.uniform(-1.0, 1.0, size=(5, 4, 3))
        for a, b in zip(remote.step_many(sequence), [local.step(actions) for actions in sequence]):
            assert_same_step(a, b)
        observation, _ = remote.reset_env(3, seed=11)
        assert np.array_equal(observation, local.reset_env(3, seed=11)[0])


def test_a_cluster_that_cannot_hold_the_envs_or_cannot_be_reached_is_a_clear_error():
    with pytest.raises(SchedulerUnreachable, match="no Dask scheduler answered at tcp://127.0.0.1:9 within 2 s"):
        hadal.env.DaskVectorEnv(2, scheduler="tcp://127.0.0.1:9", connect_timeout_s=2.0)
    with pytest.raises(ValueError, match="must be >= 1"):
        hadal.env.DaskVectorEnv(0)
    from distributed import Client, LocalCluster
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, \
            Client(cluster) as client:
        with pytest.raises(ValueError, match="5 envs at 2 per worker need 3 workers; the cluster has 1"):
            hadal.env.DaskVectorEnv(5, envs_per_worker=2, client=client)
