"""hadal.campaign: Monte Carlo campaigns of Hadal runs on a Dask cluster (Debian's python3-distributed).

    hadal-campaign run examples/campaign/cross_current.yaml                  # a LocalCluster on this machine
    hadal-campaign run FILE --scheduler tcp://10.0.0.1:8786 --out runs.csv  # any Dask cluster
    hadal-campaign cases FILE                                               # the cases, nothing run

A campaign file names a scenario, the keys to vary (grids and seeded distributions, by the override key
paths of docs/configuration.md, "Overrides"), the run's length and mode, and a metrics function of the
user's; docs/campaigns.md has every key. Each case runs as one Dask task: it starts its own hadald where the
task runs (a free DDS domain, discovery on that machine alone, so no DDS traffic crosses machines), runs it,
calls the metrics function and stops the server. The results are one table row per case, in case order:
its parameters, world seed, status and metrics; a case whose task raised is retried (also when its worker
dies) and, after its retries, reported as failed, never dropped. The same case with the same seed gives the
same metrics on any worker: hadald is deterministic and the case's parameters are drawn from the campaign
seed and the case's index alone.

Python API: load(path) -> Campaign; Campaign.cases(); run(campaign, scheduler=None, workers=None) -> Results.
"""

import argparse
import csv
import difflib
import itertools
import json
import math
import os
import socket
import sys
import tempfile
import time
import traceback

import numpy as np
import yaml

from .cluster import SchedulerUnreachable, connect

DISTRIBUTIONS = ("uniform", "normal", "loguniform", "integers", "choice")
MODES = ("lockstep", "fast")
KEYS = ("name", "scenario", "duration_s", "mode", "seed", "samples", "grid", "parameters", "overrides",
        "metrics", "keep_bags", "retries", "cameras", "threads")
REQUIRED = ("scenario", "duration_s", "metrics")
STATUS_OK, STATUS_FAILED, STATUS_INVALID = "ok", "failed", "invalid"
# Columns of the results table besides the parameters and metrics.
FIXED_COLUMNS = ("case", "seed", "status", "attempts", "worker", "wall_s")


class CampaignError(ValueError):
    """A campaign file that cannot run; `errors` are its `file:line:col: error: <path>: <what>` lines."""

    def __init__(self, path, errors):
        super().__init__(f"{path}: {len(errors)} error(s) in the campaign:\n" + "\n".join(errors))
        self.path = path
        self.errors = list(errors)


class Distribution:
    """One seeded random draw: kind in DISTRIBUTIONS and its arguments, drawn by draw(rng)."""

    def __init__(self, kind, args):
        self.kind, self.args = kind, args

    def draw(self, rng):
        if self.kind == "uniform":
            return float(rng.uniform(*self.args))
        if self.kind == "normal":
            return float(rng.normal(*self.args))
        if self.kind == "loguniform":
            low, high = self.args
            return float(math.exp(rng.uniform(math.log(low), math.log(high))))
        if self.kind == "integers":
            return int(rng.integers(self.args[0], self.args[1] + 1))
        return self.args[int(rng.integers(len(self.args)))]  # choice

    def __repr__(self):
        return f"{{{self.kind}: {self.args!r}}}"


def _draw(tree, rng):
    """tree with every Distribution replaced by a draw, in depth-first order (lists in order, maps in key order
    as written)."""
    if isinstance(tree, Distribution):
        return tree.draw(rng)
    if isinstance(tree, list):
        return [_draw(item, rng) for item in tree]
    if isinstance(tree, dict):
        return {key: _draw(value, rng) for key, value in tree.items()}
    return tree


class Case:
    """One run of a campaign: index (0-based, the table's order), parameters {key path: value}, seed (the
    world seed hadald runs with)."""

    def __init__(self, index, parameters, seed):
        self.index, self.parameters, self.seed = index, parameters, seed

    def __repr__(self):
        return f"Case({self.index}, seed={self.seed}, {self.parameters})"


class _Reader:
    """Checks a campaign file's YAML nodes, collecting `file:line:col: error: path: what` lines."""

    def __init__(self, path):
        self.path = path
        self.errors = []
        self._constructor = yaml.SafeLoader("")

    def error(self, node, where, what):
        mark = node.start_mark if node is not None else None
        position = f"{mark.line + 1}:{mark.column + 1}" if mark is not None else "1:1"
        self.errors.append(f"{self.path}:{position}: error: {where}: {what}")

    def value(self, node):
        return self._constructor.construct_object(node, deep=True)

    def number(self, node, where, minimum=None, integer=False, strictly=False):
        value = self.value(node)
        ok = isinstance(value, int) if integer else isinstance(value, (int, float))
        if isinstance(value, bool) or not ok or (not integer and not math.isfinite(value)):
            self.error(node, where, f"must be {'an integer' if integer else 'a finite number'} (got {value!r})")
            return None
        if minimum is not None and (value <= minimum if strictly else value < minimum):
            self.error(node, where, f"must be {'>' if strictly else '>='} {minimum:g} (got {value!r})")
            return None
        return value

    def tree(self, node, where, allow_distributions):
        """A parameter's value: constants, lists and maps of them, and (if allowed) distributions."""
        if isinstance(node, yaml.MappingNode):
            keys = [self.value(key) for key, _ in node.value]
            if any(key in DISTRIBUTIONS for key in keys):
                if not allow_distributions:
                    self.error(node, where, "a grid's values are constants; distributions go under parameters")
                    return None
                if len(node.value) != 1:
                    self.error(node, where, f"a distribution is a map of one key ({', '.join(DISTRIBUTIONS)}); "
                                            f"got keys {', '.join(map(str, keys))}")
                    return None
                return self.distribution(node.value[0][0], node.value[0][1], where)
            return {key: self.tree(value, f"{where}.{key}", allow_distributions)
                    for key, (_, value) in zip(keys, node.value)}
        if isinstance(node, yaml.SequenceNode):
            return [self.tree(item, f"{where}[{i}]", allow_distributions) for i, item in enumerate(node.value)]
        return self.value(node)

    def distribution(self, key_node, node, where):
        kind = self.value(key_node)
        where = f"{where}.{kind}"
        args = self.value(node)
        if kind == "choice":
            if not isinstance(args, list) or not args:
                self.error(node, where, f"needs a non-empty list of values (got {args!r})")
                return None
            return Distribution(kind, args)
        usage = {"uniform": "[low, high] with low < high", "normal": "[mean, std] with std > 0",
                 "loguniform": "[low, high] with 0 < low < high", "integers": "[low, high], integers, low <= high"}
        numbers = (isinstance(args, list) and len(args) == 2 and all(
            isinstance(a, (int, float)) and not isinstance(a, bool) and math.isfinite(a) for a in args))
        if numbers:
            a, b = args
            numbers = {"uniform": a < b, "normal": b > 0, "loguniform": 0 < a < b,
                       "integers": isinstance(a, int) and isinstance(b, int) and a <= b}[kind]
        if not numbers:
            self.error(node, where, f"needs {usage[kind]} (got {args!r})")
            return None
        return Distribution(kind, list(args))


class Campaign:
    """A checked campaign file (load(path)): the attributes are its keys (docs/campaigns.md)."""

    def __init__(self, path, name, scenario, duration_s, mode, seed, samples, grid, parameters, overrides, metrics,
                 keep_bags, retries, cameras, threads):
        self.path, self.name, self.scenario, self.duration_s, self.mode = path, name, scenario, duration_s, mode
        self.seed, self.samples, self.grid, self.parameters = seed, samples, grid, parameters
        self.overrides, self.keep_bags = overrides, keep_bags
        self.retries, self.cameras, self.threads = retries, cameras, threads
        self.metrics_file, self.metrics_function = metrics
        with open(self.metrics_file) as source:
            self.metrics_source = source.read()

    def parameter_keys(self):
        """The varied key paths, grid first, in the file's order."""
        return list(self.grid) + list(self.parameters)

    def cases(self):
        """Every case, in order: each grid point (the product of the grid's lists, the last key fastest) with
        `samples` draws of the distributions. A case's draws come from a generator seeded by (seed, index)
        alone, so a case is the same whatever other cases exist or where it runs; its world seed is drawn
        from the same sequence unless the file sets world.seed."""
        points = list(itertools.product(*self.grid.values())) if self.grid else [()]
        out = []
        for point in points:
            for _ in range(self.samples):
                index = len(out)
                sequence = np.random.SeedSequence([self.seed, index])
                world_seed = int(sequence.generate_state(1, dtype=np.uint32)[0])
                rng = np.random.default_rng(sequence)
                parameters = dict(zip(self.grid, point))
                parameters.update({key: _draw(tree, rng) for key, tree in self.parameters.items()})
                fixed = case_overrides(self.overrides, parameters)
                if "world.seed" in fixed:
                    world_seed = int(fixed["world.seed"])
                out.append(Case(index, parameters, world_seed))
        return out

    def task_spec(self):
        """What a worker needs to run a case, as plain data (pickled to the worker): the scenario's path, the
        run's settings and the metrics function's source (workers need no copy of the campaign's files)."""
        return {"scenario": self.scenario, "duration_s": self.duration_s, "mode": self.mode,
                "overrides": self.overrides, "metrics_source": self.metrics_source,
                "metrics_file": self.metrics_file, "metrics_function": self.metrics_function,
                "cameras": self.cameras, "threads": self.threads}


def load(path, scenario_lookup=None):
    """Reads and checks a campaign file; raises CampaignError with every problem found (nothing runs)."""
    from .server import scenario_path  # the same lookup as hadal.Server: a path, or a configs/scenarios name

    scenario_lookup = scenario_lookup or scenario_path
    reader = _Reader(path)
    try:
        with open(path) as f:
            text = f.read()
    except OSError as e:
        raise CampaignError(path, [f"{path}:1:1: error: cannot read the campaign file ({e.strerror})"]) from None
    try:
        root = yaml.compose(text, Loader=yaml.SafeLoader)
    except yaml.YAMLError as e:
        mark = getattr(e, "problem_mark", None)
        position = f"{mark.line + 1}:{mark.column + 1}" if mark else "1:1"
        raise CampaignError(path, [f"{path}:{position}: error: {getattr(e, 'problem', None) or e}"]) from None
    if not isinstance(root, yaml.MappingNode):
        raise CampaignError(path, [f"{path}:1:1: error: (root): a campaign file is a map of keys "
                                   f"({', '.join(REQUIRED)}, ...)"])
    nodes = {}
    for key_node, value_node in root.value:
        key = reader.value(key_node)
        if key not in KEYS:
            close = difflib.get_close_matches(str(key), KEYS, n=1)
            reader.error(key_node, str(key), f"unknown key '{key}'" + (f"; did you mean '{close[0]}'?" if close else
                                                                      f" (keys: {', '.join(KEYS)})"))
        elif key in nodes:
            reader.error(key_node, key, "given twice")
        else:
            nodes[key] = value_node
    for key in REQUIRED:
        if key not in nodes:
            reader.error(root, key, "missing (required)")
    base = os.path.dirname(os.path.abspath(path))

    def get(key, default, check):
        return check(nodes[key], key) if key in nodes else default

    def string(node, key):
        value = reader.value(node)
        if not isinstance(value, str) or not value:
            reader.error(node, key, f"must be a non-empty string (got {value!r})")
            return None
        return value

    def scenario(node, key):
        value = string(node, key)
        if value is None:
            return None
        candidate = value if os.path.isabs(value) else os.path.join(base, value)
        try:
            return scenario_lookup(candidate if os.path.isfile(candidate) else value)
        except FileNotFoundError:
            reader.error(node, key, f"no scenario {value!r} (neither a file beside the campaign file nor a name "
                                    "in configs/scenarios)")
            return None

    def mode(node, key):
        value = reader.value(node)
        if value not in MODES:
            reader.error(node, key, f"must be one of {', '.join(MODES)} (got {value!r})")
            return None
        return value

    def boolean(node, key):
        value = reader.value(node)
        if not isinstance(value, bool):
            reader.error(node, key, f"must be true or false (got {value!r})")
            return None
        return value

    def key_map(node, key, allow_distributions, grid=False):
        if not isinstance(node, yaml.MappingNode):
            reader.error(node, key, "must be a map of override key paths (world.water.current.uniform: ...)")
            return {}
        out = {}
        for key_node, value_node in node.value:
            path_key = reader.value(key_node)
            where = f"{key}.{path_key}"
            if not isinstance(path_key, str) or not path_key or "=" in path_key or " " in path_key:
                reader.error(key_node, where, "must be a key path such as world.water.current.uniform")
                continue
            if grid:
                if not isinstance(value_node, yaml.SequenceNode) or not value_node.value:
                    reader.error(value_node, where, "a grid key takes a non-empty list of values")
                    continue
                out[path_key] = [reader.tree(item, f"{where}[{i}]", False) for i, item in enumerate(value_node.value)]
            else:
                out[path_key] = reader.tree(value_node, where, allow_distributions)
        return out

    def metrics(node, key):
        value = string(node, key)
        if value is None:
            return None
        file_part, _, function = value.rpartition(":")
        if not file_part or not function.isidentifier():
            reader.error(node, key, f"must be FILE.py:FUNCTION, the file relative to the campaign file (got {value!r})")
            return None
        file_path = file_part if os.path.isabs(file_part) else os.path.join(base, file_part)
        try:
            with open(file_path) as f:
                source = f.read()
            code = compile(source, file_path, "exec")
        except OSError as e:
            reader.error(node, key, f"cannot read {file_path} ({e.strerror})")
            return None
        except SyntaxError as e:
            reader.error(node, key, f"{file_path}:{e.lineno}: {e.msg}")
            return None
        names = set(code.co_names) | {c.co_name for c in code.co_consts if hasattr(c, "co_name")}
        if function not in names:
            reader.error(node, key, f"{file_path} defines no function {function!r}")
            return None
        return os.path.abspath(file_path), function

    name = get("name", os.path.splitext(os.path.basename(path))[0], string)
    scenario_file = get("scenario", None, scenario)
    duration_s = get("duration_s", None, lambda n, k: reader.number(n, k, 0, strictly=True))
    run_mode = get("mode", "lockstep", mode)
    seed = get("seed", 0, lambda n, k: reader.number(n, k, 0, integer=True))
    samples = get("samples", 1, lambda n, k: reader.number(n, k, 1, integer=True))
    grid = get("grid", {}, lambda n, k: key_map(n, k, False, grid=True))
    parameters = get("parameters", {}, lambda n, k: key_map(n, k, True))
    overrides = get("overrides", {}, lambda n, k: key_map(n, k, False))
    metrics_spec = get("metrics", None, metrics)
    keep_bags = get("keep_bags", False, boolean)
    retries = get("retries", 2, lambda n, k: reader.number(n, k, 0, integer=True))
    cameras = get("cameras", False, boolean)
    threads = get("threads", 1, lambda n, k: reader.number(n, k, 1, integer=True))
    for key in set(grid) & set(parameters):
        reader.error(nodes["parameters"], f"parameters.{key}", "also in grid: a key is either swept or drawn")
    if keep_bags and run_mode != "fast":
        reader.error(nodes["keep_bags"], "keep_bags", "bags are recorded in mode: fast only")
    if reader.errors:
        raise CampaignError(path, reader.errors)
    campaign = Campaign(os.path.abspath(path), name, scenario_file, float(duration_s), run_mode, seed, samples, grid,
                        parameters, overrides, metrics_spec, keep_bags, retries, cameras, threads)
    if len(campaign.grid) and math.prod(len(v) for v in campaign.grid.values()) * samples > 1_000_000:
        raise CampaignError(path, [f"{path}:1:1: error: (root): more than 1,000,000 cases"])
    return campaign


def check_cases(campaign, cases, limit=64):
    """Checks the scenario with the overrides of the first case and of the first case of each grid point (at most
    `limit` checks; hadald --check, nothing starts): a misspelt key or a value out of range is found here,
    before any task starts. Raises hadal.ScenarioError."""
    from .server import check_scenario

    step = max(1, campaign.samples)
    for case in cases[::step][:limit]:
        check_scenario(campaign.scenario, overrides=case_overrides(campaign.overrides, case.parameters))


def case_overrides(constant, parameters):
    """What a case sets (hadald --set): the campaign's constant overrides, then the case's parameters (which win)."""
    merged = dict(constant)
    merged.update(parameters)
    return merged


class Run:
    """What the metrics function receives (one case's run).

    case (index), parameters ({key path: value}), seed (world seed), duration_s, mode; in lockstep mode server (a
    hadal.Server) and client (a hadal.Client that has seen its status; the function steps the run, e.g.
    run.step_to(run.duration_s)); in fast mode bag, the rosbag2 bag hadald recorded over duration_s (read it with
    hadal.bag.Bag) and no server (it has ended)."""

    def __init__(self, case, parameters, seed, duration_s, mode, server=None, client=None, bag=None):
        self.case, self.parameters, self.seed, self.duration_s, self.mode = case, parameters, seed, duration_s, mode
        self.server, self.client, self.bag = server, client, bag
        self._t_s = self._dt_s = None

    def step_to(self, t_s, chunk_s=10.0):
        """Lockstep: steps the server until its sim time reaches t_s (in requests of at most chunk_s of sim
        time); returns the sim time reached. Counts from the time its last step request returned (the server's
        status, published at a lower rate, may lag behind)."""
        if self._t_s is None:
            status = self.client.status()
            self._t_s, self._dt_s = status.sim_time, status.step_size
        while self._t_s < t_s - 0.5 * self._dt_s:
            steps = max(1, min(round((t_s - self._t_s) / self._dt_s), round(chunk_s / self._dt_s)))
            self._t_s = self.client.step(steps)
        return self._t_s


_METRICS_CACHE = {}


def _metrics_function(spec):
    """The user's metrics function, compiled from its source once per worker process."""
    key = (spec["metrics_file"], spec["metrics_function"], spec["metrics_source"])
    if key not in _METRICS_CACHE:
        namespace = {"__name__": "hadal_campaign_metrics", "__file__": spec["metrics_file"]}
        exec(compile(spec["metrics_source"], spec["metrics_file"], "exec"), namespace)
        function = namespace.get(spec["metrics_function"])
        if not callable(function):
            raise TypeError(f"{spec['metrics_file']}: {spec['metrics_function']} is not a function")
        _METRICS_CACHE[key] = function
    return _METRICS_CACHE[key]


def _checked_metrics(values, spec):
    if not isinstance(values, dict) or not values:
        raise TypeError(f"{spec['metrics_function']} must return a non-empty dict of metric names to numbers "
                        f"(got {type(values).__name__})")
    out = {}
    for name, value in values.items():
        if not isinstance(name, str) or not name or name in FIXED_COLUMNS:
            raise TypeError(f"{spec['metrics_function']}: metric name {name!r} must be a string other than "
                            f"{', '.join(FIXED_COLUMNS)}")
        if isinstance(value, (bool, np.bool_)):
            value = bool(value)
        elif isinstance(value, (int, np.integer)):
            value = int(value)
        elif isinstance(value, (float, np.floating)):
            value = float(value)
        elif not isinstance(value, str):
            raise TypeError(f"{spec['metrics_function']}: metric {name!r} must be a number, boolean or string "
                            f"(got {type(value).__name__})")
        out[name] = value
    return out


def run_case(spec, index, parameters, seed, bag_dir=None):
    """Runs one case where it is called (a Dask task): its own hadald on a free DDS domain, discovery on this
    machine only; returns {"case", "seed", "status", "worker", "wall_s", "metrics", "error"}. A scenario that
    hadald refuses (a value drawn out of range) is status "invalid", not retried; anything else raises, for
    Dask to retry."""
    from .errors import ScenarioError
    from .server import Server

    os.environ.setdefault("ROS_LOCALHOST_ONLY", "1")  # this task's DDS traffic stays on this machine
    started = time.monotonic()
    row = {"case": index, "seed": seed, "worker": _worker_name(), "metrics": {}, "error": ""}
    overrides = case_overrides(spec["overrides"], parameters)
    function = _metrics_function(spec)
    try:
        if spec["mode"] == "lockstep":
            with Server(spec["scenario"], mode="lockstep", domain_id="free", seed=seed, overrides=overrides,
                        cameras=spec["cameras"], threads=spec["threads"], die_with_parent=True) as server:
                with server.client(name="hadal_campaign") as client:
                    run = Run(index, parameters, seed, spec["duration_s"], "lockstep", server=server, client=client)
                    metrics = function(run)
        else:
            metrics = _run_fast(spec, index, parameters, seed, overrides, function, bag_dir)
    except ScenarioError as e:
        row.update(status=STATUS_INVALID, error="; ".join(e.errors), wall_s=time.monotonic() - started)
        return row
    row.update(status=STATUS_OK, metrics=_checked_metrics(metrics, spec), wall_s=time.monotonic() - started)
    return row


def _run_fast(spec, index, parameters, seed, overrides, function, bag_dir):
    """Fast mode: hadald --mode fast --duration D --record BAG on a free domain, to its end; then the metrics
    function over the bag. The bag is kept in bag_dir/case-NNNNN when bag_dir is given, else deleted."""
    import shutil
    import subprocess

    from .server import _raise_scenario_error, hadald_command, reserve_free_domain

    domain_id, lock = reserve_free_domain()
    work = tempfile.mkdtemp(prefix="hadal-campaign-")
    try:
        bag = os.path.join(work, f"case-{index:05d}")
        args = hadald_command(spec["scenario"], "fast", domain_id, seed=seed, cameras=spec["cameras"],
                              threads=spec["threads"], overrides=overrides, die_with_parent=True,
                              extra_args=("--duration", repr(spec["duration_s"]), "--record", bag,
                                          "--discovery-wait", "0"))
        env = dict(os.environ, ROS_LOCALHOST_ONLY="1")
        done = subprocess.run(args, capture_output=True, text=True, env=env)
        _raise_scenario_error(spec["scenario"], done.returncode, done.stderr)
        if done.returncode != 0:
            raise RuntimeError(f"hadald exited with status {done.returncode}:\n{done.stderr[-3000:]}")
        metrics = function(Run(index, parameters, seed, spec["duration_s"], "fast", bag=bag))
        if bag_dir is not None:
            target = os.path.join(bag_dir, f"case-{index:05d}")
            shutil.rmtree(target, ignore_errors=True)  # a retried case's earlier bag
            shutil.copytree(bag, target)
        return metrics
    finally:
        shutil.rmtree(work, ignore_errors=True)
        lock.close()


def _worker_name():
    try:
        from distributed import get_worker
        return get_worker().address
    except (ImportError, ValueError):
        return f"{socket.gethostname()}:{os.getpid()}"


class Results:
    """A campaign's outcome: rows (one dict per case, in case order: FIXED_COLUMNS, then the parameters by key
    path, then the metrics by name, then error), columns, and counts."""

    def __init__(self, campaign, rows, wall_s, workers):
        self.campaign, self.rows, self.wall_s, self.workers = campaign, rows, wall_s, workers
        metric_names = []
        for row in rows:
            for name in row["metrics"]:
                if name not in metric_names:
                    metric_names.append(name)
        self.metric_names = metric_names
        self.columns = list(FIXED_COLUMNS) + campaign.parameter_keys() + metric_names + ["error"]

    def count(self, status):
        return sum(1 for row in self.rows if row["status"] == status)

    def table(self):
        """The rows as flat dicts (the CSV's): list and map values as JSON text."""
        out = []
        for row in self.rows:
            flat = {name: row.get(name, "") for name in FIXED_COLUMNS}
            flat["wall_s"] = f"{row['wall_s']:.3f}" if isinstance(row.get("wall_s"), float) else ""
            for key in self.campaign.parameter_keys():
                flat[key] = _cell(row["parameters"].get(key, ""))
            for name in self.metric_names:
                flat[name] = _cell(row["metrics"].get(name, ""))
            flat["error"] = row.get("error", "")
            out.append(flat)
        return out

    def write_csv(self, path):
        """Writes the table to path whole or not at all (a temporary file beside it, renamed)."""
        _write_atomically(path, lambda f: _write_csv(f, self.columns, self.table()), text=True)

    def write_figure(self, path):
        """A PNG with one histogram per numeric metric over the ok cases (the campaign's summary figure)."""
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        ok = [row for row in self.rows if row["status"] == STATUS_OK]
        numeric = [name for name in self.metric_names
                   if all(isinstance(row["metrics"].get(name), (int, float)) for row in ok) and ok]
        count = max(1, len(numeric))
        columns = min(3, count)
        rows = math.ceil(count / columns)
        figure, axes = plt.subplots(rows, columns, figsize=(4.2 * columns, 3.2 * rows), squeeze=False)
        for axis in axes.flat[count:]:
            axis.set_visible(False)
        # Stacked by grid point, when there is a grid: what each swept value contributes.
        grid_keys = list(self.campaign.grid)
        groups = {}
        for row in ok:
            label = ", ".join(f"{key.rsplit('.', 1)[-1]} {_cell(row['parameters'][key])}" for key in grid_keys)
            groups.setdefault(label, []).append(row)
        for axis, name in zip(axes.flat, numeric):
            values = [np.array([float(row["metrics"][name]) for row in group]) for group in groups.values()]
            values = [v[np.isfinite(v)] for v in values]
            every = np.concatenate(values) if values else np.array([])
            bins = np.histogram_bin_edges(every, bins=max(5, min(40, int(math.sqrt(len(every))) + 1))) \
                if len(every) else 5
            axis.hist(values, bins=bins, stacked=True, edgecolor="white", label=list(groups) if grid_keys else None,
                      color=None if grid_keys else ["#2f6f9f"])
            if len(every):
                axis.axvline(float(np.mean(every)), color="black", lw=1.0, ls="--")
            axis.set_title(f"{name}\nmean {np.mean(every):.4g}, std {np.std(every):.3g}" if len(every) else name,
                           fontsize=9)
            axis.set_ylabel("cases")
            axis.grid(alpha=0.3)
        if grid_keys and numeric:
            axes.flat[0].legend(fontsize=7, frameon=False, title="grid", title_fontsize=7)
        if not numeric:
            axes.flat[0].text(0.5, 0.5, "no numeric metric over ok cases", ha="center", va="center")
        figure.suptitle(f"{self.campaign.name}: {self.count(STATUS_OK)} ok, {self.count(STATUS_FAILED)} failed, "
                        f"{self.count(STATUS_INVALID)} invalid of {len(self.rows)} cases", fontsize=11)
        figure.tight_layout()
        _write_atomically(path, lambda f: figure.savefig(f, format="png", dpi=110), text=False)
        plt.close(figure)


def _cell(value):
    if isinstance(value, (list, dict)):
        return json.dumps(value, separators=(",", ":"))
    if isinstance(value, float):
        return repr(value)
    return value


def _write_csv(f, columns, rows):
    writer = csv.DictWriter(f, fieldnames=columns, lineterminator="\n")
    writer.writeheader()
    writer.writerows(rows)


def _write_atomically(path, write, text):
    directory = os.path.dirname(os.path.abspath(path))
    os.makedirs(directory, exist_ok=True)
    handle, temporary = tempfile.mkstemp(prefix=".hadal-campaign-", dir=directory)
    try:
        with os.fdopen(handle, "w" if text else "wb", **({"newline": ""} if text else {})) as f:
            write(f)
        os.replace(temporary, path)
    except BaseException:
        os.unlink(temporary)
        raise


class _Progress:
    """A progress bar on a stream: redrawn in place on a terminal, a line per 10 % otherwise."""

    def __init__(self, total, stream):
        self.total, self.stream = total, stream
        self.tty = hasattr(stream, "isatty") and stream.isatty()
        self.started = time.monotonic()
        self.last_decile = -1

    def update(self, done, ok, failed, invalid, retried):
        if self.stream is None:
            return
        width = 30
        filled = int(width * done / max(1, self.total))
        text = (f"[{'#' * filled}{'.' * (width - filled)}] {done}/{self.total} cases: {ok} ok, {failed} failed, "
                f"{invalid} invalid, {retried} retried, {time.monotonic() - self.started:.0f} s")
        if self.tty:
            self.stream.write("\r" + text + ("\n" if done == self.total else ""))
            self.stream.flush()
        elif done * 10 // max(1, self.total) != self.last_decile or done == self.total:
            self.last_decile = done * 10 // max(1, self.total)
            self.stream.write(text + "\n")
            self.stream.flush()


START_QUEUE = "hadal-campaign-starts"


def _task(spec, index, parameters, seed, bag_dir, queue_name):
    """The Dask task: notes its start (attempts are counted from these), then runs the case."""
    from distributed import Queue
    Queue(queue_name).put(index)
    return run_case(spec, index, parameters, seed, bag_dir)


def run(campaign, scheduler=None, workers=None, client=None, progress=sys.stderr, bag_dir=None,
        connect_timeout_s=10.0, cases=None):
    """Runs every case of the campaign on Dask; returns Results (rows in case order). `client` an existing
    distributed.Client (else connect(scheduler, workers)); bag_dir where keep_bags puts each case's bag."""
    from distributed import Queue, as_completed

    cases = campaign.cases() if cases is None else cases
    own_client, cluster = (None, None) if client is not None else connect(scheduler, workers, connect_timeout_s)
    client = client or own_client
    queue_name = f"{START_QUEUE}-{os.getpid()}-{time.monotonic_ns()}"
    try:
        starts = Queue(queue_name, client=client)
        if progress is not None and not client.scheduler_info().get("workers"):
            progress.write("hadal-campaign: the scheduler has no workers yet; the cases wait for one\n")
        spec = campaign.task_spec()
        spec_future = client.scatter(spec, broadcast=True)
        started = time.monotonic()
        futures = {}
        for case in cases:
            future = client.submit(_task, spec_future, case.index, case.parameters, case.seed,
                                   bag_dir if campaign.keep_bags else None, queue_name, retries=campaign.retries,
                                   key=f"hadal-case-{case.index:05d}-{queue_name}", pure=False)
            futures[future] = case
        rows = {}
        bar = _Progress(len(cases), progress)
        attempts = {}
        counts = {STATUS_OK: 0, STATUS_FAILED: 0, STATUS_INVALID: 0}
        retried = 0

        def drain():
            nonlocal retried
            for index in starts.get(batch=True):
                attempts[index] = attempts.get(index, 0) + 1
                retried += attempts[index] == 2

        bar.update(0, 0, 0, 0, 0)
        for future in as_completed(list(futures)):
            # Once its row is here, the client lets go of the case's result: a worker that dies later holding it
            # must not have Dask run the case again to recreate it.
            case = futures.pop(future)
            if future.status == "finished":
                row = future.result()
            else:
                error = future.exception()
                detail = "".join(traceback.format_exception_only(type(error), error)).strip()
                frames = traceback.extract_tb(future.traceback()) if future.traceback() is not None else []
                if frames:  # where it was raised: the metrics function's line, or hadal's
                    detail += f" (at {frames[-1].filename}:{frames[-1].lineno}, in {frames[-1].name})"
                row = {"case": case.index, "seed": case.seed, "status": STATUS_FAILED, "worker": "",
                       "wall_s": "", "metrics": {}, "error": detail.replace("\n", " | ")}
            row["parameters"] = case.parameters
            rows[case.index] = row
            counts[row["status"]] += 1
            future.release()
            drain()
            bar.update(len(rows), counts[STATUS_OK], counts[STATUS_FAILED], counts[STATUS_INVALID], retried)
        drain()
        for index, row in rows.items():
            row["attempts"] = attempts.get(index, 0)
        worker_count = len(client.scheduler_info().get("workers", {}))
        return Results(campaign, [rows[case.index] for case in cases], time.monotonic() - started, worker_count)
    finally:
        if own_client is not None:
            own_client.close()
        if cluster is not None:
            cluster.close()


def _print_cases(campaign, cases, stream):
    keys = campaign.parameter_keys()
    _write_csv(stream, ["case", "seed"] + keys,
               [{"case": c.index, "seed": c.seed, **{k: _cell(c.parameters[k]) for k in keys}} for c in cases])


def main(argv=None):
    parser = argparse.ArgumentParser(prog="hadal-campaign", description=__doc__.splitlines()[0])
    commands = parser.add_subparsers(dest="command", required=True)
    run_parser = commands.add_parser("run", help="run every case; write the results table and its figure")
    run_parser.add_argument("file", help="the campaign file (YAML; docs/campaigns.md)")
    run_parser.add_argument("--scheduler", help="a Dask scheduler's address, tcp://HOST:8786 (default: a "
                                                "LocalCluster on this machine)")
    run_parser.add_argument("--workers", type=int, help="LocalCluster worker processes of one thread each "
                                                        "(default: one per CPU)")
    run_parser.add_argument("--out", help="the results table: .csv (default: NAME.csv beside the campaign file)")
    run_parser.add_argument("--figure", help="the summary figure, PNG (default: the table's name with .png; "
                                             "'none' for none)")
    run_parser.add_argument("--connect-timeout", type=float, default=10.0, help="seconds to reach the scheduler")
    run_parser.add_argument("--quiet", action="store_true", help="no progress bar")
    cases_parser = commands.add_parser("cases", help="print the cases (CSV) and check their overrides; nothing runs")
    cases_parser.add_argument("file")
    args = parser.parse_args(argv)

    from .errors import ScenarioError

    try:
        campaign = load(args.file)
        cases = campaign.cases()
        check_cases(campaign, cases)
    except CampaignError as e:
        print("\n".join(e.errors), file=sys.stderr)
        print(f"hadal-campaign: {len(e.errors)} error(s) in the campaign; nothing run", file=sys.stderr)
        return 1
    except ScenarioError as e:
        print("\n".join(e.errors), file=sys.stderr)
        print(f"hadal-campaign: the scenario {campaign.scenario} refuses a case's overrides; nothing run",
              file=sys.stderr)
        return 1
    if args.command == "cases":
        _print_cases(campaign, cases, sys.stdout)
        return 0
    out = args.out or os.path.join(os.path.dirname(campaign.path), campaign.name + ".csv")
    if not out.endswith(".csv"):
        print(f"hadal-campaign: error: --out {out}: the results table is a .csv file", file=sys.stderr)
        return 2
    figure = None if args.figure == "none" else (args.figure or os.path.splitext(out)[0] + ".png")
    bag_dir = os.path.splitext(out)[0] + ".bags" if campaign.keep_bags else None
    # Worker processes import hadal as this process does (a LocalCluster's, and the tasks' own hadald).
    package_root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    os.environ["PYTHONPATH"] = os.pathsep.join(p for p in (package_root, os.environ.get("PYTHONPATH")) if p)
    try:
        results = run(campaign, scheduler=args.scheduler, workers=args.workers, bag_dir=bag_dir,
                      progress=None if args.quiet else sys.stderr, connect_timeout_s=args.connect_timeout)
    except SchedulerUnreachable as e:
        print(f"hadal-campaign: error: {e}; nothing run", file=sys.stderr)
        return 2
    results.write_csv(out)
    if figure:
        results.write_figure(figure)
    failed, invalid = results.count(STATUS_FAILED), results.count(STATUS_INVALID)
    retried = sum(1 for row in results.rows if row.get("attempts", 0) > 1)
    print(f"hadal-campaign: {campaign.name}: {len(results.rows)} cases on {results.workers} worker(s) in "
          f"{results.wall_s:.1f} s: {results.count(STATUS_OK)} ok, {failed} failed, {invalid} invalid, {retried} "
          f"retried; results {out}" + (f", figure {figure}" if figure else "") + (f", bags {bag_dir}" if bag_dir else ""))
    for row in results.rows:
        if row["status"] != STATUS_OK:
            print(f"hadal-campaign: case {row['case']} {row['status']}: {row['error']}", file=sys.stderr)
    return 0 if failed == 0 and invalid == 0 else 3


if __name__ == "__main__":
    sys.exit(main())
