"""hadal.env: Gymnasium-shaped environments over lockstep hadald servers, numpy only.

    import hadal.env
    env = hadal.env.HadalEnv(task="waypoint", seed=1)       # starts its own lockstep hadald (a free domain)
    # or HadalEnv(task="waypoint", attach=True)              # the lockstep hadald on $ROS_DOMAIN_ID (else 0)
    obs, info = env.reset()
    for _ in range(100):
        obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
        if terminated or truncated:
            obs, info = env.reset()
    env.close()

    envs = hadal.env.VectorEnv(4, task="waypoint", seed=1)  # 4 servers on 4 DDS domains, stepped concurrently
    envs = hadal.env.DaskVectorEnv(8, envs_per_worker=4, scheduler="tcp://HOST:8786", task="waypoint", seed=1)
    obs, infos = envs.reset()                                # obs: (4, 12)
    obs, rewards, terminated, truncated, infos = envs.step(envs.action_space.sample())

The API is Gymnasium's (reset(seed, options) -> (observation, info); step(action) -> (observation, reward,
terminated, truncated, info); observation_space and action_space with low, high, shape, dtype, sample(),
contains(), seed()) without importing Gymnasium. When Gymnasium is importable, HadalEnv is a
gymnasium.Env, its spaces are gymnasium.spaces.Box and the tasks are registered as "Hadal/WaypointAtDepth-v0"
and "Hadal/StationKeeping-v0".

Episodes never restart the server: reset() sends a lockstep reset request (Client.reset), which starts the
run over at sim time 0 with the episode's initial pose and a sensor-noise seed drawn from the env's
np_random. So the same seed gives the same episodes, and the same actions the same observations, bit for bit.

Tasks (TASKS; each says where its observation comes from):
  "waypoint"         WaypointAtDepth: the default scenario's torpedo AUV (cameras off), 3 thrusters; reach a
                     random point 10-20 m away and 3-8 m shallower. Ground-truth observation.
  "station_keeping"  StationKeeping: the vectored ROV of configs/scenarios/rov.yaml in a 0.3 m/s current,
                     8 thrusters; hold the start point. Sensor observation (DVL, IMU, pressure) plus a
                     position fix.
"""

import math
import os

import numpy as np

from ._hadal import Client, current_cpu, default_domain_id
from .errors import Timeout, UnknownVehicle
from .frames import rotation_matrix, yaw
from .server import Server

try:  # optional: only to be a registered gymnasium.Env with gymnasium spaces
    import gymnasium
except ImportError:  # Debian 12 has no Gymnasium package
    gymnasium = None

# Seawater and air as hadald's defaults (configs/REFERENCE.md, "world.water"): depth from absolute pressure.
P_ATM_PA = 101325.0
RHO_KG_M3 = 1025.0
G_M_S2 = 9.80665


class Box:
    """A box in R^n with the attributes of gymnasium.spaces.Box: low, high, shape, dtype, np_random;
    sample() (uniform where bounded, normal where not), contains(x), seed(seed)."""

    def __init__(self, low, high, shape=None, dtype=np.float32, seed=None):
        self.dtype = np.dtype(dtype)
        shape = tuple(shape) if shape is not None else np.shape(low)
        self.low = np.broadcast_to(np.asarray(low, dtype=self.dtype), shape).copy()
        self.high = np.broadcast_to(np.asarray(high, dtype=self.dtype), shape).copy()
        self.shape = shape
        self.np_random = np.random.default_rng(seed)

    def seed(self, seed=None):
        self.np_random = np.random.default_rng(seed)
        return [seed]

    def is_bounded(self):
        return bool(np.all(np.isfinite(self.low)) and np.all(np.isfinite(self.high)))

    def sample(self):
        bounded = np.isfinite(self.low) & np.isfinite(self.high)
        value = self.np_random.standard_normal(self.shape)
        uniform = self.np_random.uniform(np.where(bounded, self.low, 0.0), np.where(bounded, self.high, 1.0))
        return np.where(bounded, uniform, value).astype(self.dtype)

    def contains(self, x):
        x = np.asarray(x)
        return x.shape == self.shape and bool(np.all(x >= self.low) and np.all(x <= self.high))

    __contains__ = contains

    def __repr__(self):
        return f"Box({self.low.min()}, {self.high.max()}, {self.shape}, {self.dtype})"


def _box(low, high, shape, dtype=np.float32):
    if gymnasium is not None:
        return gymnasium.spaces.Box(low=low, high=high, shape=shape, dtype=dtype)
    return Box(low, high, shape, dtype)


def _yawed(pose_q, yaw):
    """The quaternion (x, y, z, w) of a rotation by `yaw` about W's z after pose_q."""
    h = 0.5 * yaw
    qz = np.array([0.0, 0.0, math.sin(h), math.cos(h)])
    x1, y1, z1, w1 = qz
    x2, y2, z2, w2 = pose_q
    return np.array([w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2, w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
                     w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2, w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2])


class Task:
    """What an episode is: the scenario and vehicle, the control period, how an episode starts, what is
    observed, and the reward. Subclass it for a task of your own and pass an instance as HadalEnv(task=...)."""

    scenario = "default"
    vehicle = "auv"
    cameras = False           # start the server with the scenario's cameras
    num_actions = 0           # the vehicle's control vector: one entry per actuator, [-1, 1]
    # Joint actions after the control vector, for an articulated vehicle: ((controller, ((low, high), ...)),
    # ...), one action per joint of each named joint controller (a position, velocity or effort group), its
    # [-1, 1] mapped linearly onto [low, high] (rad or m, rad/s or m/s, N m or N) and held until the next
    # step; the episode starts with the scenario's joint commands.
    joint_actions = ()
    control_period_s = 0.1    # sim time per env step
    max_episode_steps = 600
    observation_names = ()

    def start(self, rng, scenario_pose):
        """The episode's initial pose {vehicle: (x, y, z, qx, qy, qz, qw)} (at rest), drawn from rng;
        scenario_pose is the vehicle's pose in the scenario (p_WB, q_WB)."""
        raise NotImplementedError

    def observe(self, env, t):
        """The observation (float32, len(observation_names)) at sim time t [s]: from env.ground_truth() (the
        vehicle's state carried by the step reply) and env.sensor(...) (the sensors' topics)."""
        raise NotImplementedError

    def reward(self, env, observation, action):
        """(reward, terminated, info) after a step."""
        raise NotImplementedError


class WaypointAtDepth(Task):
    """Reach a waypoint at another depth: the default scenario's torpedo AUV (3 thrusters: main, heave,
    sway in the nose) starts at its scenario pose with a random heading (+-30 deg); the waypoint lies 10-20 m
    away, within +-45 deg of the start heading, 3-8 m shallower (clear of the seabed and the lander).
    Observation: ground truth (the state each lockstep reply carries, as odometry would). Reward: the metres
    gained towards the waypoint in the step, less 0.01 |a|^2; +10 and terminated within 1 m of it. Truncated
    after 60 s (600 steps of 0.1 s). The AUV is ~1 N buoyant, so with the thrusters off it rises towards the
    (shallower) waypoint and earns a little (~+1.6 in 20 s): a policy has to beat doing nothing, not only
    random actions."""

    scenario = "default"
    vehicle = "auv"
    num_actions = 3
    control_period_s = 0.1
    max_episode_steps = 600
    success_radius_m = 1.0
    observation_names = ("goal_x_B", "goal_y_B", "goal_z_B",      # waypoint in B [m]
                         "v_x_B", "v_y_B", "v_z_B",               # velocity in B [m/s]
                         "w_x_B", "w_y_B", "w_z_B",               # angular velocity in B [rad/s]
                         "up_x_B", "up_y_B", "up_z_B")            # W's z axis in B (attitude)

    def start(self, rng, scenario_pose):
        p, q = scenario_pose
        yaw0 = yaw(q)
        heading = yaw0 + rng.uniform(-math.radians(30), math.radians(30))
        bearing = yaw0 + rng.uniform(-math.radians(45), math.radians(45))
        distance = rng.uniform(10.0, 20.0)
        self.goal_W = np.array([p[0] + distance * math.cos(bearing), p[1] + distance * math.sin(bearing),
                                p[2] + rng.uniform(3.0, 8.0)])
        self.last_distance = None
        return {self.vehicle: (*p, *_yawed(q, heading - yaw0))}

    def observe(self, env, t):
        odom = env.ground_truth()
        R_WB = rotation_matrix(odom.q_WB)
        offset_W = self.goal_W - odom.p_WB
        self.distance = math.sqrt(offset_W @ offset_W)
        observation = np.empty(12, dtype=np.float32)
        observation[0:3] = offset_W @ R_WB  # R_WB^T offset
        observation[3:6] = odom.v_WB_B
        observation[6:9] = odom.w_WB_B
        observation[9:12] = R_WB[2]
        return observation

    def reward(self, env, observation, action):
        progress = 0.0 if self.last_distance is None else self.last_distance - self.distance
        self.last_distance = self.distance
        reward = progress - 0.01 * float(action @ action)
        success = self.distance < self.success_radius_m
        if success:
            reward += 10.0
        return reward, success, {"distance_m": self.distance, "is_success": success}


class StationKeeping(Task):
    """Hold a point in a current: the vectored ROV of configs/scenarios/rov.yaml (8 thrusters) in a 0.3 m/s
    current starts up to 1 m (0.5 m in depth, 0.3 rad in heading) from its station, the scenario's pose.
    Observation: the sensors -- DVL bottom-track velocity (DVL frame), IMU rate and specific force (IMU
    frame), depth error from the pressure sensor (metres below the station depth, for the sensor's mounting
    0.2 m above B when level) -- and a position fix standing in for USBL: the horizontal offset from the
    station in W and the heading error as sin and cos, from ground truth. Reward: -(horizontal and depth
    offset [m]) - 0.01 |a|^2 per step; terminated beyond 10 m. Truncated after 60 s (300 steps of 0.2 s,
    the DVL's 5 Hz)."""

    scenario = "rov"
    vehicle = "rov"
    num_actions = 8
    control_period_s = 0.2
    max_episode_steps = 300
    lost_m = 10.0   # terminated beyond this offset
    held_m = 0.5    # info["is_success"] within this offset
    sensors = {"dvl": 5.0, "imu": 50.0, "depth": 10.0}  # name: rate [Hz], configs/vehicles/vectored_rov.yaml
    depth_sensor_above_B_m = 0.2                         # its pose there
    observation_names = ("dvl_v_x", "dvl_v_y", "dvl_v_z",         # [m/s], DVL frame
                         "imu_w_x", "imu_w_y", "imu_w_z",         # [rad/s], IMU frame
                         "imu_f_x", "imu_f_y", "imu_f_z",         # specific force [m/s^2], IMU frame
                         "depth_error",                           # [m], + deeper than the station
                         "offset_x_W", "offset_y_W",              # position fix [m]
                         "sin_heading_error", "cos_heading_error")

    def start(self, rng, scenario_pose):
        p, q = scenario_pose
        self.station_W = np.array(p)
        self.station_yaw = yaw(q)
        offset = np.array([rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0), rng.uniform(-0.5, 0.5)])
        return {self.vehicle: (*(self.station_W + offset), *_yawed(q, rng.uniform(-0.3, 0.3)))}

    def observe(self, env, t):
        dvl = env.sensor("wait_dvl", "dvl", t, self.sensors["dvl"])
        imu = env.sensor("wait_imu", "imu", t, self.sensors["imu"])
        pressure = env.sensor("wait_fluid_pressure", "depth", t, self.sensors["depth"])
        odom = env.ground_truth()
        depth_B = (pressure.pressure - P_ATM_PA) / (RHO_KG_M3 * G_M_S2) + self.depth_sensor_above_B_m
        depth_error = depth_B + self.station_W[2]
        offset = odom.p_WB - self.station_W
        heading_error = yaw(odom.q_WB) - self.station_yaw
        self.offset_m = float(math.hypot(offset[0], offset[1]) + abs(depth_error))
        velocity = dvl.velocity if dvl.velocity_mode != dvl.VELOCITY_MODE_NONE else np.zeros(3)
        return np.concatenate([velocity, imu.angular_velocity, imu.linear_acceleration, [depth_error],
                               offset[:2], [math.sin(heading_error), math.cos(heading_error)]]).astype(np.float32)

    def reward(self, env, observation, action):
        lost = self.offset_m > self.lost_m
        info = {"offset_m": self.offset_m, "is_success": self.offset_m < self.held_m}
        return -self.offset_m - 0.01 * float(action @ action), lost, info


TASKS = {"waypoint": WaypointAtDepth, "station_keeping": StationKeeping}

_EnvBase = gymnasium.Env if gymnasium is not None else object


class _Closing:
    """close() on leaving a `with` block, and when garbage-collected at the latest."""

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False

    def __del__(self):
        try:
            self.close()
        except Exception:
            pass


class HadalEnv(_Closing, _EnvBase):
    """One environment: a task on a lockstep hadald (its own, or the one on domain_id).

    HadalEnv(task="waypoint" | "station_keeping" | a Task, seed=None, scenario=None, attach=False,
             domain_id=None, max_episode_steps=None, timeout_s=30.0, hadald=None, threads=None, cpus=None,
             sched=None, lockstep_spin_us=None)

    attach=False (the default) starts the env's own lockstep server (hadal.Server) on domain_id, by default
    "free" (an id in 100..199 no other hadal.Server holds, so several envs run side by side), and stops it on
    close(). attach=True uses the lockstep hadald already running on domain_id (None: $ROS_DOMAIN_ID, else 0,
    as every Hadal tool), which must run the task's scenario, and leaves it running; scenario, hadald, threads,
    cpus, sched and lockstep_spin_us are then refused (they describe a server to start). scenario overrides the
    task's (a name in configs/scenarios or a path); threads, cpus, sched and lockstep_spin_us go to its server
    (hadal.Server: the CPU threads it computes on, the CPUs it runs on, its scheduling policy, how long it
    polls for the next request); die_with_parent=True has its server killed when
    the thread that made the env ends (hadal.Server: DaskVectorEnv's, whose worker may be killed). Each step applies the action (the vehicle's control vector, clipped to [-1, 1]) for the task's
    control period, then observes. info: sim_time [s], episode_step, and the task's figures.
    """

    metadata = {"render_modes": []}
    render_mode = None
    spec = None

    def __init__(self, task="waypoint", seed=None, scenario=None, attach=False, domain_id=None,
                 max_episode_steps=None, timeout_s=30.0, hadald=None, threads=None, cpus=None, sched=None,
                 die_with_parent=False, lockstep_spin_us=None):
        if not isinstance(attach, bool):
            raise TypeError(f"attach must be True or False (got {attach!r})")
        if attach:
            starts = {name: value for name, value in (("scenario", scenario), ("hadald", hadald),
                                                      ("threads", threads), ("cpus", cpus), ("sched", sched),
                                                      ("lockstep_spin_us", lockstep_spin_us))
                      if value is not None}
            if starts:
                raise ValueError(f"attach=True uses a running server: {', '.join(starts)} would describe one to "
                                 "start (leave them out, or attach=False)")
        self.task = TASKS[task]() if isinstance(task, str) else task
        self.timeout_s = timeout_s
        self.max_episode_steps = max_episode_steps or self.task.max_episode_steps
        self.observation_space = _box(-np.inf, np.inf, (len(self.task.observation_names),))
        self._joint_actions = [(controller, np.array([low for low, _ in ranges], dtype=np.float64),
                                np.array([high for _, high in ranges], dtype=np.float64))
                               for controller, ranges in self.task.joint_actions]
        self._num_actions = self.task.num_actions + sum(low.size for _, low, _ in self._joint_actions)
        self.action_space = _box(-1.0, 1.0, (self._num_actions,))
        self.np_random = np.random.default_rng(seed)
        # Its own stream, not the episode stream of an env seeded seed + 1 (VectorEnv seeds env i with seed + i).
        self.action_space.seed(None if seed is None else int(np.random.default_rng([seed, 0xAC7]).integers(2**31)))
        self._seeded = seed is not None
        self.server = None
        if attach:
            domain_id = default_domain_id() if domain_id is None else domain_id
        else:
            self.server = Server(scenario or self.task.scenario, mode="lockstep", hadald=hadald,
                                 domain_id="free" if domain_id is None else domain_id, cameras=self.task.cameras,
                                 threads=threads, cpus=cpus, sched=sched, die_with_parent=die_with_parent,
                                 lockstep_spin_us=lockstep_spin_us)
            domain_id = self.server.domain_id
        try:
            self.client = self._connect(domain_id)
        except BaseException:
            if self.server is not None:
                self.server.stop()
            raise
        self.domain_id = domain_id
        self._scenario_pose = None
        self._time = 0.0
        self._steps = 0
        self._started = False

    def _connect(self, domain_id):
        client = Client(domain_id=domain_id, name="hadal_env")
        if not client.wait_for_server(self.timeout_s):
            client.close()
            raise Timeout(f"no hadald status on DDS domain {domain_id} within {self.timeout_s} s")
        status = client.status()
        self._dt = status.step_size
        if self.task.vehicle not in status.vehicle_names:
            client.close()
            raise UnknownVehicle(f"the task's vehicle {self.task.vehicle!r} is not in the scenario "
                                 f"({', '.join(status.vehicle_names)})", self.task.vehicle)
        return client

    @property
    def frame_skip(self):
        """Physics steps per env step."""
        return max(1, round(self.task.control_period_s / self._dt))

    # -- what tasks read -------------------------------------------------------------------------------
    def ground_truth(self):
        """The vehicle's ground truth (an Odometry: p_WB, q_WB, v_WB_B, w_WB_B) at the last reply's sim time: the
        numbers its odometry carries at that instant, taken from the lockstep reply (Client.reply_odometry), so
        the env needs no odometry subscription."""
        return self.client.reply_odometry(self.task.vehicle)

    def sensor(self, wait, name, t, rate_hz):
        """The sensor's last sample due at or before sim time t (rate_hz: its rate)."""
        due = math.floor(t * rate_hz + 1e-6) / rate_hz
        sample = getattr(self.client, wait)(self.task.vehicle, name, min_stamp=due - 1e-9, timeout_s=self.timeout_s)
        if sample is None:
            raise Timeout(f"no sample of {self.task.vehicle}/{name} at t = {due:.3f} s within {self.timeout_s} s")
        return sample

    # -- the Gymnasium API ------------------------------------------------------------------------------
    def reset(self, *, seed=None, options=None):
        """Starts an episode: (observation, info). seed reseeds np_random (and the episode's draws follow
        from it); options may give {"pose": (x, y, z[, qx, qy, qz, qw])} to start there instead."""
        return self._begin_reset(seed, options)()

    def step(self, action):
        """Applies `action` for one control period: (observation, reward, terminated, truncated, info)."""
        return self._begin_step(action)()

    # reset() and step() in two halves: the request is sent, and the returned function waits for the reply
    # and observes. VectorEnv sends to every env before it waits for any, so the servers step in parallel.
    def _begin_reset(self, seed, options):
        if seed is not None:
            self.np_random = np.random.default_rng(seed)
            self._seeded = True
        if self._scenario_pose is None:  # the scenario's own start, read once at t = 0
            self.client.reset(timeout_s=self.timeout_s)
            odom = self.ground_truth()
            self._scenario_pose = (np.array(odom.p_WB), np.array(odom.q_WB))
        poses = self.task.start(self.np_random, self._scenario_pose)
        if options and "pose" in options:
            poses = {self.task.vehicle: tuple(options["pose"])}
        noise_seed = int(self.np_random.integers(0, 2**63))
        self.client.set_commands(self.task.vehicle, [0.0] * self.task.num_actions, publish=False)
        request = self.client.send_reset(seed=noise_seed, poses=poses, steps=self.frame_skip,
                                         timeout_s=self.timeout_s)

        def finish():
            self._time = self.client.wait_reply(request, timeout_s=self.timeout_s)
            self._steps = 0
            observation = self.task.observe(self, self._time)
            self.task.reward(self, observation, np.zeros(self._num_actions))  # the task's reference point
            self._started = True
            return observation, {"sim_time": self._time, "episode_step": 0, "noise_seed": noise_seed}
        return finish

    def _begin_step(self, action):
        if not self._started:
            raise RuntimeError("HadalEnv.step() before reset(): call reset() to start an episode")
        action = np.asarray(action, dtype=np.float64).reshape(self._num_actions)
        if not np.isfinite(action).all():
            raise ValueError(f"action has non-finite entries: {action}")
        action = np.minimum(np.maximum(action, -1.0), 1.0)  # np.clip, without its per-call checks
        at = self.task.num_actions
        self.client.set_commands(self.task.vehicle, action[:at].tolist(), publish=False)
        for controller, low, high in self._joint_actions:
            share = action[at:at + low.size]
            at += low.size
            values = low + 0.5 * (share + 1.0) * (high - low)
            self.client.set_joint_commands(self.task.vehicle, controller, values.tolist(), publish=False)
        request = self.client.send_step(self.frame_skip, timeout_s=self.timeout_s)

        def finish():
            self._time = self.client.wait_reply(request, timeout_s=self.timeout_s)
            self._steps += 1
            observation = self.task.observe(self, self._time)
            reward, terminated, info = self.task.reward(self, observation, action)
            truncated = not terminated and self._steps >= self.max_episode_steps
            info.update(sim_time=self._time, episode_step=self._steps)
            return observation, float(reward), bool(terminated), bool(truncated), info
        return finish

    def render(self):
        return None

    def close(self):
        """Leaves the domain and stops the env's own server. Idempotent."""
        if getattr(self, "client", None) is not None:
            self.client.close()
        if getattr(self, "server", None) is not None:
            self.server.stop()

    @property
    def unwrapped(self):
        return self


def _env_seeds(seed, num_envs):
    """A vector env's reset seeds: an int gives env i seed + i, a list one per env (None: that env's stream goes
    on), None none."""
    if seed is None or isinstance(seed, (int, np.integer)):
        return [None if seed is None else int(seed) + i for i in range(num_envs)]
    seeds = [None if s is None else int(s) for s in seed]
    if len(seeds) != num_envs:
        raise ValueError(f"{len(seeds)} seeds for {num_envs} envs")
    return seeds


class VectorEnv(_Closing):
    """n HadalEnvs, each with its own lockstep hadald on its own DDS domain, stepped concurrently from this
    process: every call sends all n requests before it waits for any reply, so the servers step in parallel
    while this thread observes the envs whose replies have come (docs/benchmarks.md, "Lockstep round
    trip and the Python client").

    reset(seed=None) -> (observations (n, ...), infos: list of n dicts); seed: an int (env i gets seed + i) or
    a list of n seeds (None entries leave that env's stream alone).
    step(actions (n, ...)) -> (observations, rewards (n,), terminated (n,), truncated (n,), infos). With
    autoreset (the default) an env whose episode ended is reset in the same call: its row of observations is
    the new episode's first and its info keeps the last one as info["final_observation"] (and
    info["final_info"]). Without it, an ended env must be reset (reset_env(i)) before its next step.
    Keyword arguments other than these go to each HadalEnv (envs[i] is env i). An error in one env is raised
    after every request sent has been answered, so the others stay in step.

    The servers share the CPUs this process may run on. With pin_cpus (the default) server i runs on CPU
    share i alone, max(1, CPUs // n) CPUs taken in turn (hadald --cpus), and computes on as many threads;
    and its wake-ups do not preempt this thread (hadald --sched batch). Both keep the servers stepping in
    parallel on a small machine: unpinned, the kernel moves their threads between cores (cold caches) and
    the first server's wake-up can take the core from this thread before it has sent the second request
    (docs/benchmarks.md); the servers on the CPU this thread runs on get their requests last, for the same
    reason. pin_cpus=False leaves placement to the kernel, each server on max(1, CPUs // n) threads; so
    should several VectorEnvs stepping at once on one machine, as they would share CPU 0 first.
    """

    def __init__(self, num_envs, task="waypoint", seed=None, autoreset=True, pin_cpus=True, **kwargs):
        if num_envs < 1:
            raise ValueError(f"num_envs must be >= 1 (got {num_envs})")
        for shared in ("attach", "domain_id"):
            if shared in kwargs:
                raise ValueError(f"VectorEnv starts one server per env, each on a free domain: {shared} is not "
                                 "taken (use HadalEnv to attach to a running server)")
        cpus = sorted(os.sched_getaffinity(0))
        share = max(1, len(cpus) // num_envs)
        self.pin_cpus = pin_cpus and "cpus" not in kwargs
        # Servers sharing cores sleep between requests: polling for the next (hadald --lockstep-spin-us, which
        # saves a lone server its wake-up) would take a core from the server beside it.
        kwargs.setdefault("lockstep_spin_us", 0)
        if self.pin_cpus:
            shares = [[cpus[(i * share + k) % len(cpus)] for k in range(share)] for i in range(num_envs)]
            kwargs.setdefault("sched", "batch")
        else:
            shares = [kwargs.pop("cpus", None)] * num_envs
            kwargs.setdefault("threads", share)
        self.num_envs = num_envs
        self.autoreset = autoreset
        self.envs = []
        try:
            for i in range(num_envs):
                self.envs.append(HadalEnv(task=task, seed=None if seed is None else seed + i, cpus=shares[i],
                                          **kwargs))
        except BaseException:
            self.close()
            raise
        self.domain_ids = [env.domain_id for env in self.envs]
        single = self.envs[0]
        self.single_observation_space = single.observation_space
        self.single_action_space = single.action_space
        self.observation_space = _box(-np.inf, np.inf, (num_envs, *single.observation_space.shape))
        self.action_space = _box(-1.0, 1.0, (num_envs, *single.action_space.shape))
        self.action_space.seed(
            None if seed is None else int(np.random.default_rng([seed, 0xAC7, num_envs]).integers(2**31)))

    def _all(self, calls):
        """calls: (env, begin) pairs. Calls each begin() (sending the env's request), then each finish() it
        returned; the results in the order of calls. The first error is raised once every request sent has
        been answered.

        Pinned, the envs whose servers run on this thread's CPU get their requests last: such a server's
        threads wake on this CPU and can run their whole step there before this thread has sent the other
        servers their requests (docs/benchmarks.md, "Lockstep round trip and the Python client")."""
        order = list(range(len(calls)))
        if self.pin_cpus and len(calls) > 1:
            cpu = current_cpu()
            # Stable: the others keep their order.
            order.sort(key=lambda k: cpu in (getattr(calls[k][0].server, "cpus", None) or ()))
        finishes, error = {}, None
        for k in order:
            try:
                finishes[k] = calls[k][1]()
            except BaseException as raised:
                error = error or raised
        results = [None] * len(calls)
        for k in order:
            if k not in finishes:
                continue
            try:
                results[k] = finishes[k]()
            except BaseException as raised:
                error = error or raised
        if error is not None:
            raise error
        return results

    def reset(self, *, seed=None, options=None):
        seeds = _env_seeds(seed, self.num_envs)
        results = self._all([(env, lambda env=env, s=s: env._begin_reset(s, options))
                              for env, s in zip(self.envs, seeds)])
        return np.stack([r[0] for r in results]), [r[1] for r in results]

    def reset_env(self, index, seed=None, options=None):
        """Resets env `index` alone: (observation, info)."""
        return self.envs[index].reset(seed=seed, options=options)

    def step(self, actions):
        actions = np.asarray(actions, dtype=np.float64).reshape(self.action_space.shape)
        results = self._all([(env, lambda env=env, a=a: env._begin_step(a)) for env, a in zip(self.envs, actions)])
        observations = [r[0] for r in results]
        infos = [r[4] for r in results]
        ended = [i for i, r in enumerate(results) if r[2] or r[3]] if self.autoreset else []
        if ended:  # the ended envs start their next episodes, concurrently too
            starts = self._all([(self.envs[i], lambda env=self.envs[i]: env._begin_reset(None, None))
                                for i in ended])
            for i, (observation, reset_info) in zip(ended, starts):
                infos[i] = dict(infos[i], final_observation=observations[i], final_info=dict(infos[i]),
                                reset_info=reset_info)
                observations[i] = observation
        return (np.stack(observations), np.array([r[1] for r in results]), np.array([r[2] for r in results]),
                np.array([r[3] for r in results]), infos)

    def close(self):
        """Closes every env, stopping its server. Idempotent."""
        for env in self.envs:
            env.close()
        self.envs = []


class _EnvGroup:
    """A Dask actor (DaskVectorEnv): a VectorEnv of `count` envs in a worker process, env k seeded seed + k, each
    with its own lockstep hadald on a free domain of the worker's machine (discovery on that machine alone)."""

    def __init__(self, count, task, seed, autoreset, kwargs):
        os.environ.setdefault("ROS_LOCALHOST_ONLY", "1")
        self.vector = VectorEnv(count, task=task, seed=seed, autoreset=autoreset, die_with_parent=True, **kwargs)

    def shapes(self):
        return (self.vector.single_observation_space.shape, self.vector.single_action_space.shape,
                self.vector.domain_ids)

    def reset(self, seeds, options):
        return self.vector.reset(seed=seeds, options=options)

    def reset_env(self, index, seed, options):
        return self.vector.reset_env(index, seed=seed, options=options)

    def step(self, actions):
        return self.vector.step(actions)

    def step_many(self, action_sequence):
        """Several steps in one call: the results of step() for each actions array of the sequence."""
        return [self.vector.step(actions) for actions in action_sequence]

    def ping(self):
        return None

    def close(self):
        self.vector.close()


class DaskVectorEnv(_Closing):
    """VectorEnv's API with the envs on the workers of a Dask cluster (Debian's python3-distributed): each worker
    holds envs_per_worker envs (a Dask actor with a VectorEnv of them, each env with its own lockstep hadald on
    that worker's machine), so one network round trip per worker carries that many env steps, and the workers'
    envs step in parallel. Env i is seeded seed + i, as in VectorEnv, and with the same actions gives the
    same observations, to the bit.

    DaskVectorEnv(num_envs, envs_per_worker=4, scheduler=None, client=None, task="waypoint", seed=None,
                  autoreset=True, workers=None, **kwargs)

    scheduler: a Dask scheduler's address (tcp://HOST:8786); client: a distributed.Client to use; neither: a
    LocalCluster of ceil(num_envs / envs_per_worker) single-threaded workers on this machine. The envs are
    spread over the cluster's workers in turn (at most envs_per_worker on each; `workers`: the addresses to use).
    kwargs go to each VectorEnv (pin_cpus=False by default: a worker's servers run on any CPU it may use).
    step_many(action_sequence) runs several steps in one round trip (open-loop actions: a policy evaluated
    on the worker side, or a replay)."""

    def __init__(self, num_envs, envs_per_worker=4, scheduler=None, client=None, task="waypoint", seed=None,
                 autoreset=True, workers=None, connect_timeout_s=10.0, **kwargs):
        from .cluster import connect

        if num_envs < 1 or envs_per_worker < 1:
            raise ValueError(f"num_envs and envs_per_worker must be >= 1 (got {num_envs}, {envs_per_worker})")
        self.num_envs, self.autoreset = num_envs, autoreset
        self.groups, self._actors, self._cluster, self._own_client = [], [], None, None
        groups = -(-num_envs // envs_per_worker)
        if client is None:
            client, self._cluster = connect(scheduler, None if scheduler else groups, connect_timeout_s)
            self._own_client = client
        self.client = client
        try:
            addresses = list(workers) if workers else sorted(client.scheduler_info()["workers"])
            if not addresses:
                raise RuntimeError("the Dask cluster has no workers")
            if len(addresses) * envs_per_worker < num_envs:
                raise ValueError(f"{num_envs} envs at {envs_per_worker} per worker need "
                                 f"{groups} workers; the cluster has {len(addresses)}")
            kwargs.setdefault("pin_cpus", False)
            first = 0
            for g in range(groups):
                count = min(envs_per_worker, num_envs - first)
                future = client.submit(_EnvGroup, count, task, None if seed is None else seed + first, autoreset,
                                       kwargs, actor=True, workers=[addresses[g % len(addresses)]],
                                       allow_other_workers=False, pure=False)
                self._actors.append(future)
                self.groups.append((first, count, addresses[g % len(addresses)]))
                first += count
            self.actors = [future.result() for future in self._actors]
            shapes = [actor.shapes().result() for actor in self.actors]
        except BaseException:
            self.close()
            raise
        observation_shape, action_shape, _ = shapes[0]
        self.domain_ids = [d for _, _, ids in shapes for d in ids]
        self.single_observation_space = _box(-np.inf, np.inf, observation_shape)
        self.single_action_space = _box(-1.0, 1.0, action_shape)
        self.observation_space = _box(-np.inf, np.inf, (num_envs, *observation_shape))
        self.action_space = _box(-1.0, 1.0, (num_envs, *action_shape))
        self.action_space.seed(
            None if seed is None else int(np.random.default_rng([seed, 0xAC7, num_envs]).integers(2**31)))

    def _gather(self, futures):
        """Every actor's result, the first error raised once all have answered (the others stay in step)."""
        results, error = [], None
        for future in futures:
            try:
                results.append(future.result())
            except BaseException as raised:
                results.append(None)
                error = error or raised
        if error is not None:
            raise error
        return results

    @staticmethod
    def _joined(parts):
        """Concatenates per-group (observations, rewards, terminated, truncated, infos) tuples."""
        return (np.concatenate([p[0] for p in parts]), np.concatenate([p[1] for p in parts]),
                np.concatenate([p[2] for p in parts]), np.concatenate([p[3] for p in parts]),
                [info for p in parts for info in p[4]])

    def reset(self, *, seed=None, options=None):
        seeds = _env_seeds(seed, self.num_envs)
        parts = self._gather([actor.reset(seeds[first:first + count], options)
                              for actor, (first, count, _) in zip(self.actors, self.groups)])
        return np.concatenate([p[0] for p in parts]), [info for p in parts for info in p[1]]

    def reset_env(self, index, seed=None, options=None):
        """Resets env `index` alone: (observation, info)."""
        for actor, (first, count, _) in zip(self.actors, self.groups):
            if first <= index < first + count:
                return actor.reset_env(index - first, seed, options).result()
        raise IndexError(f"env {index} of {self.num_envs}")

    def step(self, actions):
        actions = np.asarray(actions, dtype=np.float64).reshape(self.action_space.shape)
        return self._joined(self._gather([actor.step(actions[first:first + count])
                                          for actor, (first, count, _) in zip(self.actors, self.groups)]))

    def step_many(self, action_sequence):
        """Steps with each (num_envs, ...) actions array of the sequence in turn, one round trip per worker for
        them all; returns the list of step() results."""
        sequence = np.asarray(action_sequence, dtype=np.float64).reshape(-1, *self.action_space.shape)
        per_group = self._gather([actor.step_many(list(sequence[:, first:first + count]))
                                  for actor, (first, count, _) in zip(self.actors, self.groups)])
        return [self._joined([group[k] for group in per_group]) for k in range(len(sequence))]

    def ping(self):
        """One empty round trip to every worker's actor (what a step costs beyond the envs' own work)."""
        self._gather([actor.ping() for actor in self.actors])

    def close(self):
        """Closes every env (stopping its server), the actors, and the cluster this object started. Idempotent."""
        for actor in getattr(self, "actors", []):
            try:
                actor.close().result()
            except Exception:
                pass
        self.actors = []
        for future in getattr(self, "_actors", []):
            future.release()
        self._actors = []
        if getattr(self, "_own_client", None) is not None:
            self._own_client.close()
            self._own_client = None
        if getattr(self, "_cluster", None) is not None:
            self._cluster.close()
            self._cluster = None


if gymnasium is not None:  # pragma: no cover - Gymnasium is not a Debian 12 package
    for _id, _task in (("Hadal/WaypointAtDepth-v0", "waypoint"), ("Hadal/StationKeeping-v0", "station_keeping")):
        if _id not in gymnasium.registry:
            gymnasium.register(id=_id, entry_point="hadal.env:HadalEnv", kwargs={"task": _task},
                               max_episode_steps=TASKS[_task].max_episode_steps)
