"""hadal.env against real lockstep hadald processes: the Gymnasium API shape, seeded episodes that repeat bit
for bit without a server restart, both tasks' observations, and VectorEnv's concurrent servers."""

import math
import os

import numpy as np
import pytest

import hadal
import hadal.env
from hadal.server import reserve_domain

from conftest import SESSION_DOMAINS


def rollout(env, seed, steps):
    """Observations and rewards of one episode under a seeded random policy."""
    actions = np.random.default_rng(seed).uniform(-1.0, 1.0, (steps, env.action_space.shape[0]))
    observation, info = env.reset(seed=seed)
    observations, rewards = [observation], []
    for action in actions:
        observation, reward, terminated, truncated, info = env.step(action)
        observations.append(observation)
        rewards.append(reward)
    return np.array(observations), np.array(rewards)


def test_the_gymnasium_api_shape():
    with hadal.env.HadalEnv(task="waypoint", seed=1, max_episode_steps=5) as env:
        with pytest.raises(RuntimeError, match="before reset"):
            env.step([0.0, 0.0, 0.0])
        assert env.observation_space.shape == (12,) and env.action_space.shape == (3,)
        assert env.action_space.dtype == np.float32
        assert np.all(env.action_space.low == -1.0) and np.all(env.action_space.high == 1.0)
        observation, info = env.reset()
        assert observation.dtype == np.float32 and observation in env.observation_space
        assert info["sim_time"] == pytest.approx(0.1) and info["episode_step"] == 0
        # The waypoint is 10-20 m away and 3-8 m up: its offset in B says so (the AUV starts level).
        assert 10.0 <= np.linalg.norm(observation[:2]) <= 21.0 and 2.5 <= observation[2] <= 8.5
        np.testing.assert_allclose(observation[9:], [0.0, 0.0, 1.0], atol=1e-3)  # W's z in B: level
        for k in range(5):
            action = env.action_space.sample()
            assert action in env.action_space
            observation, reward, terminated, truncated, info = env.step(action)
            assert isinstance(reward, float) and not terminated
            assert truncated == (k == 4)  # max_episode_steps
        assert info["sim_time"] == pytest.approx(0.6) and info["episode_step"] == 5
        with pytest.raises(ValueError):
            env.step([math.nan, 0.0, 0.0])
        pid = env.server.process.pid
    assert not env.server.running and pid > 0


def test_attaching_to_a_running_server_is_asked_for_and_leaves_it_running():
    """attach=True uses the lockstep server on $ROS_DOMAIN_ID (or domain_id) and never stops it; a domain_id
    alone starts the env's own server there (it no longer means attach); VectorEnv takes neither."""
    with hadal.Server("default", mode="lockstep") as server:  # on the session's $ROS_DOMAIN_ID
        with hadal.env.HadalEnv(task="waypoint", seed=1, attach=True) as env:
            assert env.server is None and env.domain_id == server.domain_id
            env.reset(seed=1)
            env.step(np.zeros(env.action_space.shape))
        assert server.running
        with pytest.raises(ValueError, match="attach=True uses a running server: scenario would describe one"):
            hadal.env.HadalEnv(task="waypoint", attach=True, scenario="rov")
        with pytest.raises(ValueError, match="attach=True uses a running server: lockstep_spin_us would describe one"):
            hadal.env.HadalEnv(task="waypoint", attach=True, lockstep_spin_us=0)
    domain_id, handle = reserve_domain(SESSION_DOMAINS)  # no other test uses it; the env's server takes it
    handle.close()
    with hadal.env.HadalEnv(task="waypoint", seed=1, domain_id=domain_id) as own:
        assert own.server is not None and own.server.domain_id == domain_id
    assert not own.server.running
    with pytest.raises(ValueError, match="VectorEnv starts one server per env, each on a free domain: attach"):
        hadal.env.VectorEnv(2, attach=True)


def test_the_same_seed_gives_the_same_observations():
    with hadal.env.HadalEnv(task="waypoint", seed=0) as a, hadal.env.HadalEnv(task="waypoint", seed=0) as b:
        assert a.domain_id != b.domain_id
        first, first_rewards = rollout(a, seed=7, steps=30)
        np.testing.assert_array_equal(first, rollout(b, seed=7, steps=30)[0])  # another server
        again, again_rewards = rollout(a, seed=7, steps=30)                   # the same server, reset
        np.testing.assert_array_equal(first, again)
        np.testing.assert_array_equal(first_rewards, again_rewards)
        other, _ = rollout(a, seed=8, steps=30)
        assert not np.array_equal(first, other)  # another waypoint and start
        assert np.abs(first[-1, 3]) > 0.05       # and it moved


def test_station_keeping_observes_the_sensors():
    with hadal.env.HadalEnv(task="station_keeping", seed=2) as env:
        assert env.action_space.shape == (8,) and env.observation_space.shape == (14,)
        start = np.array([0.6, -0.4, 0.3, 0.0, 0.0, 0.0, 1.0])  # 0.3 m above the station, level
        observation, info = env.reset(options={"pose": start + [0, 0, -90.0, 0, 0, 0, 0]})
        assert info["sim_time"] == pytest.approx(0.2)
        # Depth error from the pressure sensor: 0.3 m above the station. Bounds: its noise (200 Pa: 0.02 m)
        # and 0.2 s of rising on the ROV's positive buoyancy (seen: 0.03 m).
        assert observation[9] == pytest.approx(-0.3, abs=0.06)
        # The position fix: the offset as placed, less 0.2 s of drift in the 0.3 m/s current.
        np.testing.assert_allclose(observation[10:12], [0.6, -0.4], atol=0.1)
        # At rest the IMU feels +g along its z and almost no rotation.
        assert observation[8] == pytest.approx(9.81, abs=0.3)
        assert np.all(np.abs(observation[3:6]) < 0.1)
        for _ in range(50):  # left alone for 10 s it drifts east with the current (> 0.5 m, the ROV example)
            observation, reward, terminated, truncated, info = env.step(np.zeros(8))
        assert observation[10] > 0.6 + 0.3 and reward < 0.0
        assert info["offset_m"] == pytest.approx(-reward, rel=1e-6)


def test_vector_env_steps_servers_concurrently():
    with hadal.env.VectorEnv(2, task="waypoint", seed=3, max_episode_steps=3) as envs:
        assert envs.observation_space.shape == (2, 12) and envs.action_space.shape == (2, 3)
        assert len(set(envs.domain_ids)) == 2
        # Pinned (the default): server i runs on CPU share i, max(1, CPUs // 2) CPUs taken in turn, on as
        # many threads, every thread of it SCHED_BATCH.
        cpus = sorted(os.sched_getaffinity(0))
        share = max(1, len(cpus) // 2)
        for i, env in enumerate(envs.envs):
            mine = {cpus[(i * share + k) % len(cpus)] for k in range(share)}
            with open(env.server.log_path) as log:
                assert f", {share} thread(s) on CPU(s) " in log.readline()
            tasks = [int(tid) for tid in os.listdir(f"/proc/{env.server.process.pid}/task")]
            assert len(tasks) > 1  # DDS's threads too
            for tid in tasks:
                assert os.sched_getaffinity(tid) == mine
                assert os.sched_getscheduler(tid) == os.SCHED_BATCH
            # Servers sharing cores sleep at once between requests instead of polling (hadald --lockstep-spin-us).
            with open(f"/proc/{env.server.process.pid}/cmdline") as cmdline:
                args = cmdline.read().split("\0")
            assert args[args.index("--lockstep-spin-us") + 1] == "0"
        if len(cpus) >= 2:  # the server pinned to this thread's CPU is sent its request last
            before = os.sched_getaffinity(0)
            try:
                for mine, other in ((0, 1), (1, 0)):
                    os.sched_setaffinity(0, envs.envs[mine].server.cpus)
                    sent = []
                    results = envs._all([(env, lambda i=i: sent.append(i) or (lambda i=i: i))
                                         for i, env in enumerate(envs.envs)])
                    assert sent == [other, mine] and results == [0, 1]
            finally:
                os.sched_setaffinity(0, before)
        observations, infos = envs.reset(seed=3)
        assert observations.shape == (2, 12) and len(infos) == 2
        assert not np.array_equal(observations[0], observations[1])  # seeds 3 and 4
        for k in range(3):
            observations, rewards, terminated, truncated, infos = envs.step(envs.action_space.sample())
            assert observations.shape == (2, 12) and rewards.shape == (2,)
        assert np.all(truncated)  # the third step ends both episodes; both were reset in the same call
        for info in infos:
            assert info["final_observation"].shape == (12,)
            assert info["reset_info"]["episode_step"] == 0
        # Seeded like two single envs with seeds 3 and 4.
        with hadal.env.HadalEnv(task="waypoint", seed=4) as single:
            first, _ = single.reset(seed=4)
        np.testing.assert_array_equal(envs.reset(seed=3)[0][1], first)
        np.testing.assert_array_equal(envs.reset(seed=[4, 4])[0][0], first)  # one seed per env


def test_vector_env_raises_an_envs_error_and_leaves_nothing_running():
    with pytest.raises(KeyError):
        hadal.env.VectorEnv(2, task="no_such_task")
    with hadal.env.VectorEnv(2, task="waypoint", seed=1, pin_cpus=False) as envs:
        threads = max(1, len(os.sched_getaffinity(0)) // 2)  # unpinned: the kernel places the servers
        for env in envs.envs:
            with open(env.server.log_path) as log:
                assert f", {threads} thread(s) on CPU(s) " in log.readline()
            assert os.sched_getaffinity(env.server.process.pid) == os.sched_getaffinity(0)
            assert os.sched_getscheduler(env.server.process.pid) == os.SCHED_OTHER
        envs.reset()
        with pytest.raises(ValueError, match="non-finite"):
            envs.step([[0.0, 0.0, 0.0], [math.nan, 0.0, 0.0]])
        # Env 0's request went out and its reply was awaited before the error was raised; env 1 sent none.
        assert [env._steps for env in envs.envs] == [1, 0]
        envs.step(np.zeros((2, 3)))  # both still answer
        servers = [env.server.process for env in envs.envs]
    assert all(server.poll() is not None for server in servers)


class ShoulderReach(hadal.env.Task):
    """A task of one joint action on the articulated test scenario: the arm's shoulder position group, its
    [-1, 1] mapped onto [-60, 60] degrees; observed: both joints' positions."""

    scenario = os.path.join(os.environ.get("HADAL_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "../../..")),
                            "tests/integration/scenarios/arm.yaml")
    vehicle = "arm"
    num_actions = 0  # the frame has no thrusters
    joint_actions = (("shoulder_position", ((math.radians(-60.0), math.radians(60.0)),)),)
    observation_names = ("shoulder", "forearm")

    def start(self, rng, scenario_pose):
        return {self.vehicle: np.concatenate(scenario_pose)}

    def observe(self, env, t):
        joints = env.client.wait_joint_state(self.vehicle, min_stamp=t - 1e-9, timeout_s=env.timeout_s)
        return np.asarray(joints.position, dtype=np.float32)

    def reward(self, env, observation, action):
        return 0.0, False, {}


def test_joint_actions_command_an_arms_position_group():
    """Task.joint_actions puts a position group's joints in the action space after the control vector: +1
    drives the shoulder to 60 degrees, -0.5 to -30 (each within 3 degrees: the gravity sag of kp = 400), and
    a reset starts the next episode from the scenario's joints (the shoulder at 30 degrees)."""
    with hadal.env.HadalEnv(task=ShoulderReach(), seed=3, max_episode_steps=100) as env:
        assert env.action_space.shape == (1,)
        observation, _ = env.reset()
        assert abs(observation[0] - math.radians(30.0)) < math.radians(3.0)
        for _ in range(30):  # 3 s
            observation, *_ = env.step([1.0])
        assert abs(observation[0] - math.radians(60.0)) < math.radians(3.0), np.degrees(observation)
        for _ in range(30):
            observation, *_ = env.step([-0.5])
        assert abs(observation[0] - math.radians(-30.0)) < math.radians(3.0), np.degrees(observation)
        observation, _ = env.reset()
        assert abs(observation[0] - math.radians(30.0)) < math.radians(3.0), np.degrees(observation)
