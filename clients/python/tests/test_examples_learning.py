"""examples/python/random_rollout.py, train_waypoint.py and lawnmower_survey.py, each run in a short form as a
subprocess that starts its own lockstep hadald(s) (~30 s in all on 2 cores)."""

import os
import subprocess
import sys

import numpy as np
import pytest

from conftest import SOURCE_DIR

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def run_example(name, *args, cwd=None):
    """Runs examples/python/<name> with `args`; returns (stdout lines, {key: value} of its key=value lines)."""
    env = dict(os.environ)
    env.setdefault("ROS_LOCALHOST_ONLY", "1")
    if env.get("HADALD"):
        env["HADALD"] = os.path.abspath(env["HADALD"])
    if env.get("PYTHONPATH"):  # the subprocess may run elsewhere: absolute entries
        env["PYTHONPATH"] = os.pathsep.join(os.path.abspath(p) for p in env["PYTHONPATH"].split(os.pathsep) if p)
    result = subprocess.run([sys.executable, os.path.join(SOURCE_DIR, "examples", "python", name), *map(str, args)],
                            env=env, cwd=cwd, capture_output=True, text=True, timeout=180)
    assert result.returncode == 0, result.stdout + result.stderr
    lines = result.stdout.splitlines()
    figures = {}
    for line in lines:
        key, _, value = line.partition("=")
        if value and " " not in key:
            figures[key] = value
    return lines, figures


@pytest.mark.parametrize("envs", [1, 2])
def test_random_rollout_reports_every_episode(envs):
    """Three episodes of 20 steps (2 s). None can end early: the waypoint is at least 10 m away and the AUV,
    from rest, makes at most ~1.8 m/s at full thrust. So each return, metres gained towards the waypoint
    less 0.01 |a|^2 per step, lies within +-(3.6 m + 20 x 0.03) < 5."""
    lines, figures = run_example("random_rollout.py", "--episodes", 3, "--steps", 20, "--seed", 0, "--envs", envs)
    episodes = [line for line in lines if line.startswith("episode ")]
    assert len(episodes) == 3 and int(figures["episodes"]) == 3
    returns = [float(line.split("return=")[1].split()[0]) for line in episodes]
    assert all(np.isfinite(returns)) and all(abs(r) < 5.0 for r in returns)
    assert all("length=20 " in line and "success=False" in line for line in episodes)
    assert float(figures["mean_return"]) == pytest.approx(np.mean(returns), abs=1e-3)
    # envs=2: two rounds of two episodes, the fourth unfinished in count but stepped
    assert int(figures["env_steps"]) == (60 if envs == 1 else 80)
    assert float(figures["env_steps_per_s"]) > 0.0


def test_train_waypoint_writes_a_policy_and_is_deterministic(tmp_path):
    """Two iterations of 4 candidates on one 3 s episode each: too little to assert learning (the ranking
    of 4 random policies on one episode says little, and the mean policy is scored on other, held-out seeds),
    so this checks the mechanics: the saved shapes, the all-thrusters-off start (over 3 s the AUV only
    floats up on its ~1 N of buoyancy: a return within +-0.5 m), and that the run depends on --seed alone,
    not on how many servers evaluate the candidates (one lockstep episode is a function of its seed and
    actions)."""
    short = ["--iterations", 2, "--population", 4, "--elite", 2, "--episodes", 1, "--eval-episodes", 2,
             "--episode-steps", 30, "--seed", 3]
    lines, figures = run_example("train_waypoint.py", *short, "--envs", 2, "--save", tmp_path / "policy.npz")
    assert sum(line.startswith("iteration ") for line in lines) == 3  # 0 (the start) .. 2
    assert abs(float(figures["initial_mean_return"])) < 0.5
    for key in ("initial_mean_return", "final_mean_return", "improvement", "initial_population_mean_return"):
        assert np.isfinite(float(figures[key]))
    assert float(figures["improvement"]) == pytest.approx(
        float(figures["final_mean_return"]) - float(figures["initial_mean_return"]), abs=1e-3)
    policy = np.load(tmp_path / "policy.npz")
    assert policy["W"].shape == (3, 12) and policy["b"].shape == (3,) and policy["obs_scale"].shape == (12,)
    assert policy["sigma"].shape == (39,) and policy["curve"].shape == (2, 4)
    assert all(np.all(np.isfinite(policy[key])) for key in policy.files)
    assert np.any(policy["W"] != 0.0)  # moved off the start (mu = 0)

    _, again = run_example("train_waypoint.py", *short, "--envs", 1, "--save", tmp_path / "again.npz")
    for key in ("initial_mean_return", "initial_population_mean_return", "final_mean_return"):
        assert again[key] == figures[key]
    np.testing.assert_array_equal(np.load(tmp_path / "again.npz")["W"], policy["W"])


def test_lawnmower_survey_saves_lit_frames_of_a_moving_camera(tmp_path):
    """One 3 m leg (~5 s from rest), every 10th frame: frames at 1, 2, ... s.

    Brightness: at ~100 m in Jerlov III water daylight is ~1e-4 of the surface's (~0.02 W/m^2), ~1 count
    through this camera (0.1 count/e- x 0.02 s x 2e5 e-/s per W/(m^2 sr): 400 counts per W/(m^2 sr)): the
    frames are black without the AUV's lights. With them, 2 x 300 W/sr on the seabed ~8 m along the optical
    axis (4 m up, 30 deg down, light at 60 deg incidence) through ~16 m of water there and back
    (c ~ 0.08-0.12 /m in blue and green, red mostly absorbed) and an albedo ~0.25, the image centre gets
    ~25-40 counts in green and blue, more in the nearer bottom rows plus backscatter (measured: mean 62-65
    over the channels; R ~29, G ~70, B ~92). The bound, 15, is an order of magnitude above the unlit frame.
    Blue over red: the water absorbs red (pure-water absorption ~0.4 /m vs ~0.02 /m).
    Motion: the frames are 16 x 16 px block averages apart by more than 1 count (measured: 2.5 counts after
    1 s, 5 after 4 s), well above what the sensor's shot noise leaves after averaging (~2.5 / 16 counts)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out = tmp_path / "survey"
    _, figures = run_example("lawnmower_survey.py", "--legs", 1, "--leg-length", 3, "--every", 10, "--out", out)
    frames = sorted(out.glob("frame_*.png"))
    assert int(figures["frames_saved"]) == len(frames) >= 2
    assert int(figures["legs"]) == 1
    assert 2.5 < float(figures["distance_m"]) < 4.5  # the 3 m leg, ended within one 0.1 s step past its end
    assert float(figures["max_depth_excursion_m"]) < 0.3
    images = []
    for path in frames:
        assert path.read_bytes()[:8] == PNG_SIGNATURE
        image = plt.imread(path)[..., :3] * 255.0
        assert image.shape == (480, 640, 3)
        assert image.mean() > 15.0
        assert image[..., 2].mean() > image[..., 0].mean()
        images.append(image)
    assert float(figures["mean_brightness"]) == pytest.approx(np.mean([i.mean() for i in images]), abs=0.5)

    def blocks(image):
        return image.reshape(30, 16, 40, 16, 3).mean(axis=(1, 3))

    assert np.abs(blocks(images[-1]) - blocks(images[0])).mean() > 1.0
    assert (out / "survey.png").read_bytes()[:8] == PNG_SIGNATURE
