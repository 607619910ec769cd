"""hadal.Server: launch and stop a hadald process from Python.

    import hadal
    with hadal.Server("rov", mode="lockstep") as server:      # configs/scenarios/rov.yaml
        client = hadal.Client(domain_id=server.domain_id)
        client.wait_for_server()
        t = client.step(100)

The server runs on $ROS_DOMAIN_ID (else 0), as hadald does, or on the domain_id given ("free": one no other
hadal.Server holds); each hadal.Server holds its domain (a lock file per id, /tmp/hadal-dds-domain-<id>.lock,
as the test suite's) so two never share one. It is awaited until it publishes its status, keeps its log
(server.log_path), and is stopped on leaving the `with` block -- also when the block raises -- or by
stop(), at the latest when the interpreter exits.

Logs go to one folder, LOG_ROOT (<tmp>/hadal-server-logs-<uid>/hadald-*/hadald.log), which keeps the LOGS_KEPT
newest: each new Server deletes the older logs of servers that have stopped, never a running one's.
"""

import atexit
import fcntl
import json
import os
import re
import shutil
import subprocess
import tempfile
import time

from ._hadal import Client, default_domain_id
from .errors import ScenarioError, ServerNotFound

LOG_ROOT = os.path.join(tempfile.gettempdir(), f"hadal-server-logs-{os.getuid()}")
LOGS_KEPT = 20


def _open_log_dir(root, keep):
    """A new log folder under root, held (an flock on its `running` file) until release; then deletes the
    folders beyond the `keep` newest whose servers have stopped (nobody holds their lock)."""
    os.makedirs(root, mode=0o700, exist_ok=True)
    log_dir = tempfile.mkdtemp(prefix="hadald-", dir=root)
    held = open(os.path.join(log_dir, "running"), "w")
    fcntl.flock(held, fcntl.LOCK_EX)
    folders = []
    for name in os.listdir(root):
        path = os.path.join(root, name)
        if name.startswith("hadald-") and path != log_dir:
            try:
                folders.append((os.stat(path).st_mtime, path))
            except FileNotFoundError:  # another process pruned it meanwhile
                pass
    folders.sort(reverse=True)
    for _, path in folders[max(keep - 1, 0):]:
        try:
            with open(os.path.join(path, "running")) as lock:
                fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)  # raises while its server runs
        except BlockingIOError:
            continue
        except FileNotFoundError:
            pass
        shutil.rmtree(path, ignore_errors=True)
    return log_dir, held


try:  # written by the build (clients/python/CMakeLists.txt): where hadald and the configs are
    from . import _build_paths
except ImportError:  # pragma: no cover - an installed package without build paths
    _build_paths = None


def find_hadald(explicit=None):
    """The hadald executable: `explicit`, $HADALD, the build tree's, or hadald on PATH."""
    candidates = [explicit, os.environ.get("HADALD"), getattr(_build_paths, "HADALD", None), shutil.which("hadald")]
    for candidate in candidates:
        if candidate and os.path.isfile(candidate) and os.access(candidate, os.X_OK):
            return candidate
    raise ServerNotFound("hadald not found (pass hadald=..., set HADALD, or put it on PATH); tried "
                         + ", ".join(repr(c) for c in candidates if c))


def scenario_path(scenario):
    """A scenario file: a path as given, or a name of configs/scenarios/<name>.yaml."""
    if os.path.isfile(scenario):
        return os.path.abspath(scenario)
    config_dir = getattr(_build_paths, "CONFIG_DIR", None)
    if config_dir:
        named = os.path.join(config_dir, "scenarios", scenario + ".yaml")
        if os.path.isfile(named):
            return named
    raise FileNotFoundError(f"no scenario {scenario!r} (neither a file nor a name in configs/scenarios)")


# A command prefix that has the kernel SIGKILL the command when the thread that started it ends (util-linux's
# setpriv, in every Debian): a server of a Dask task dies with a worker killed by kill -9 instead of running on.
DIE_WITH_PARENT = ("setpriv", "--pdeathsig", "KILL", "--")

FREE_DOMAINS = range(100, 200)  # where domain_id="free" looks for an unused domain


def _lock_path(domain_id):
    return f"/tmp/hadal-dds-domain-{domain_id}.lock"


def reserve_domain(candidates):
    """The first DDS domain id of `candidates` no other process holds, as (id, lock file handle; close it to
    release), or None. The same lock files as the test suite and tools: /tmp/hadal-dds-domain-<id>.lock, which
    holds the holder's pid."""
    for candidate in candidates:
        handle = open(_lock_path(candidate), "a")
        try:
            fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            handle.close()
            continue
        handle.truncate(0)
        handle.write(f"{os.getpid()}\n")
        handle.flush()
        return candidate, handle
    return None


def reserve_free_domain():
    """reserve_domain(FREE_DOMAINS): (id, lock file handle); ServerNotFound when every one is held."""
    reserved = reserve_domain(FREE_DOMAINS)
    if reserved is None:
        raise ServerNotFound(f"no free DDS domain id in {FREE_DOMAINS.start}..{FREE_DOMAINS.stop - 1}")
    return reserved


def _holder(domain_id):
    """' (pid N)' of the process holding the domain's lock file, or ''."""
    try:
        with open(_lock_path(domain_id)) as lock:
            pid = lock.read().strip()
    except OSError:
        return ""
    return f" (pid {pid})" if pid.isdigit() else ""


def override_arguments(overrides):
    """hadald --set arguments ("KEY.PATH=VALUE") for Server(overrides=...): a dict's items, each value written
    as YAML in flow style (JSON is that: numbers, lists, dicts, strings, booleans), or a list of strings as they
    are. None: none."""
    if overrides is None:
        return []
    if isinstance(overrides, dict):
        out = []
        for key, value in overrides.items():
            if not isinstance(key, str) or not key:
                raise ValueError(f"an override's key must be a non-empty key path string (got {key!r})")
            try:
                text = json.dumps(value, allow_nan=False)
            except (TypeError, ValueError) as e:
                raise ValueError(f"override {key}: the value {value!r} cannot be written as YAML ({e})") from None
            out.append(f"{key}={text}")
        return out
    if isinstance(overrides, str):
        raise ValueError("overrides must be a dict or a list of 'KEY.PATH=VALUE' strings, not one string")
    return [str(item) for item in overrides]


def hadald_command(scenario, mode, domain_id, hadald=None, seed=None, cameras=True, threads=None, cpus=None,
                   sched=None, security_file=None, overrides=None, die_with_parent=False, extra_args=(),
                   lockstep_spin_us=None):
    """hadald's command line for a scenario file (Server's options, which see), without a status line."""
    args = [*(DIE_WITH_PARENT if die_with_parent else ()), find_hadald(hadald), scenario, "--mode", mode,
            "--domain-id", str(domain_id), "--no-status-line", *extra_args]
    if seed is not None:
        args += ["--seed", str(int(seed))]
    if not cameras:
        args.append("--no-cameras")
    if threads is not None:
        args += ["--threads", str(int(threads))]
    if cpus is not None:
        args += ["--cpus", ",".join(str(int(cpu)) for cpu in cpus)]
    if sched is not None:
        args += ["--sched", str(sched)]
    if lockstep_spin_us is not None:
        args += ["--lockstep-spin-us", str(int(lockstep_spin_us))]
    if security_file is not None:
        args += ["--security", os.fspath(security_file)]
    for override in override_arguments(overrides):
        args += ["--set", override]
    return args


def _raise_scenario_error(scenario, returncode, output):
    """ScenarioError when hadald's output says it refused the scenario (its `file:line:col: error:` lines and
    "nothing started", exit status 1); otherwise returns."""
    lines = output.splitlines()
    if returncode != 1 or not any(line.endswith("in the scenario; nothing started") for line in lines):
        return
    errors = [line for line in lines if re.match(r".*:\d+:\d+: error: ", line)]
    if errors:
        raise ScenarioError(scenario, errors)


def check_scenario(scenario, overrides=None, hadald=None, timeout_s=60.0):
    """Loads and checks a scenario with its overrides as Server would (hadald --check: nothing starts); raises
    ScenarioError with hadald's `file:line:col: error:` lines if it is refused, returns the scenario's path
    otherwise."""
    path = scenario_path(scenario)
    args = [find_hadald(hadald), path, "--check"]
    for override in override_arguments(overrides):
        args += ["--set", override]
    done = subprocess.run(args, capture_output=True, text=True, timeout=timeout_s)
    _raise_scenario_error(path, done.returncode, done.stderr)
    if done.returncode != 0:
        raise ServerNotFound(f"hadald --check {path} exited with status {done.returncode}:\n{done.stderr[-2000:]}")
    return path


class Server:
    """A hadald process: Server(scenario, mode="lockstep" | "fast" | "realtime", domain_id=None, seed=None).

    domain_id None takes the domain every Hadal tool and ROS 2 take ($ROS_DOMAIN_ID, else 0), so `ros2 topic list`
    sees the server; "free" picks an id in 100..199 that no other hadal.Server holds (several servers at once,
    as hadal.env does); a domain held by another hadal.Server raises ServerNotFound naming its pid. seed overrides the scenario's world.seed; cameras=False leaves
    the scenario's cameras out (hadald --no-cameras); threads caps the CPU threads it computes on (hadald
    --threads; None: the scenario's world.threads, by default one per CPU it may run on); cpus (a list of CPU
    numbers) keeps all its threads on those CPUs (hadald --cpus); sched="batch" keeps its wake-ups from
    preempting other threads, such as the client stepping it (hadald --sched batch); lockstep_spin_us is how
    long a lockstep server polls for the next request after each reply before it sleeps (hadald
    --lockstep-spin-us; None: hadald's 200, 0: sleep at once, for servers that share cores). ready_timeout_s
    bounds the wait for its first status; a malformed scenario raises ScenarioError with hadald's
    `file:line:col: error:` lines, a server that exits first for another reason ServerNotFound with its
    log's end. extra_args go to hadald's command line as they are.

    overrides set keys of the scenario as if its file said so (hadald --set, checked like the file; a bad one
    raises ScenarioError): a dict {"world.water.current.uniform": [0.4, 0, 0], "vehicles.auv.initial_pose":
    {"position": [0, 0, -50]}} (values as YAML: numbers, lists, dicts, strings, booleans) or a list of
    "KEY.PATH=VALUE" strings, in order (a later one wins). Key paths as in docs/configuration.md, "Overrides".

    die_with_parent=True has the kernel kill the server when the thread that made this object ends, also by
    kill -9 of its process (hadal.campaign's tasks: a killed Dask worker leaves no server behind); the thread
    must then outlive the server.

    security_file turns DDS Security on (hadald --security: a YAML file with hadald's `security:` block, as
    tools/make-security-demo.sh writes it); client_security_file is then the identity of the clients this
    object makes (its readiness probe, client()), by default the same file.
    """

    def __init__(self, scenario, mode="lockstep", domain_id=None, seed=None, hadald=None, ready_timeout_s=30.0,
                 extra_args=(), cameras=True, threads=None, cpus=None, sched=None, security_file=None,
                 client_security_file=None, overrides=None, die_with_parent=False, lockstep_spin_us=None):
        if mode not in ("lockstep", "fast", "realtime"):
            raise ValueError(f"mode must be 'lockstep', 'fast' or 'realtime' (got {mode!r})")
        self.scenario = scenario_path(scenario)
        self.mode = mode
        self.threads = threads  # --threads, or None (the scenario's world.threads)
        self.cpus = None if cpus is None else [int(cpu) for cpu in cpus]  # --cpus, or None (any CPU)
        self._lock = None
        self._log_held = None
        self.domain_id = self._reserve(domain_id)
        self._log_dir, self._log_held = _open_log_dir(LOG_ROOT, LOGS_KEPT)
        self.log_path = os.path.join(self._log_dir, "hadald.log")
        args = hadald_command(self.scenario, mode, self.domain_id, hadald=hadald, seed=seed, cameras=cameras,
                              threads=threads, cpus=cpus, sched=sched, security_file=security_file,
                              overrides=overrides, die_with_parent=die_with_parent, extra_args=extra_args,
                              lockstep_spin_us=lockstep_spin_us)
        self.client_security_file = client_security_file if client_security_file is not None else security_file
        env = dict(os.environ)
        env.setdefault("ROS_LOCALHOST_ONLY", "1")
        with open(self.log_path, "w") as log:
            self.process = subprocess.Popen(args, stdout=log, stderr=subprocess.STDOUT, env=env)
        atexit.register(self.stop)
        try:
            self._await_ready(ready_timeout_s)
        except BaseException:
            self.stop()
            raise

    def _reserve(self, domain_id):
        if isinstance(domain_id, str) and domain_id == "free":
            reserved = reserve_free_domain()
        else:
            if domain_id is None:
                domain_id = default_domain_id()
            elif isinstance(domain_id, bool) or not isinstance(domain_id, int) or not 0 <= domain_id <= 232:
                raise ValueError("domain_id must be an integer in 0..232, None ($ROS_DOMAIN_ID, else 0) or 'free' "
                                 f"(an unused one in {FREE_DOMAINS.start}..{FREE_DOMAINS.stop - 1}); got {domain_id!r}")
            reserved = reserve_domain([domain_id])
            if reserved is None:
                raise ServerNotFound(f"DDS domain {domain_id} is held by another hadal.Server{_holder(domain_id)}: "
                                     "stop it, or pass another domain_id, or domain_id='free' for an unused one")
        candidate, self._lock = reserved
        return candidate

    def _await_ready(self, timeout_s):
        with Client(domain_id=self.domain_id, name="hadal_server_probe",
                    security_file=self.client_security_file) as client:
            deadline = time.monotonic() + timeout_s
            while time.monotonic() < deadline:
                if self.process.poll() is not None:
                    self._raise_scenario_error()
                    raise ServerNotFound(f"hadald exited with status {self.process.returncode} before it was "
                                         "ready:\n" + self.log_tail(60))
                if client.wait_for_server(0.2):
                    return
        raise ServerNotFound(f"hadald published no status within {timeout_s} s:\n" + self.log_tail())

    def _raise_scenario_error(self):
        """ScenarioError when hadald refused the scenario (its `file:line:col: error:` lines and "nothing
        started"); otherwise returns."""
        with open(self.log_path, errors="replace") as log:
            _raise_scenario_error(self.scenario, self.process.returncode, log.read())

    def client(self, name="hadal_python", timeout_s=10.0):
        """A Client on this server's domain that has seen its status (close it, or use it in a `with`)."""
        client = Client(domain_id=self.domain_id, name=name, security_file=self.client_security_file)
        if not client.wait_for_server(timeout_s):
            client.close()
            raise ServerNotFound(f"no status from hadald on domain {self.domain_id} within {timeout_s} s")
        return client

    def log_tail(self, lines=20):
        """The last lines of the server's log."""
        with open(self.log_path, errors="replace") as log:
            return "".join(log.readlines()[-lines:])

    @property
    def running(self):
        return self.process is not None and self.process.poll() is None

    def stop(self, timeout_s=20.0):
        """Stops the server (SIGTERM, then SIGKILL after timeout_s); returns its exit status. Idempotent."""
        if self.process is not None and self.process.poll() is None:
            self.process.terminate()
            try:
                self.process.wait(timeout=timeout_s)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()
        if self._lock is not None:
            self._lock.close()
            self._lock = None
        if self._log_held is not None:  # the log stays until LOGS_KEPT newer servers have started
            self._log_held.close()
            self._log_held = None
        atexit.unregister(self.stop)
        return None if self.process is None else self.process.returncode

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.stop()
        return False

    def __repr__(self):
        state = "running" if self.running else f"exited {self.process.returncode}"
        return f"<hadal.Server {os.path.basename(self.scenario)} {self.mode} domain {self.domain_id} {state}>"
