"""pathfarm through its command-line client: a farm of local processes, and a shot that is
submitted, followed, fetched and cancelled. Nothing here imports bpy, so it runs (and is
tested) outside Blender too."""

import os
import re
import secrets
import shutil
import subprocess
import time

PROGRESS = re.compile(r"shot (\d+): (\d+)/(\d+) tasks")
LOG_PREFIX = re.compile(r"^\[[0-9:]+\] (\w+) ")


class FarmError(Exception):
    """A message for the artist: what went wrong, without a traceback."""


def find_executable(configured=""):
    candidate = configured or os.environ.get("PATHFARM") or shutil.which("pathfarm") or ""
    candidate = os.path.abspath(os.path.expanduser(candidate)) if candidate else ""
    if not candidate or not os.access(candidate, os.X_OK):
        raise FarmError("pathfarm executable not found: set it in the pathfarm panel, or $PATHFARM")
    return candidate


def last_error(text, lines=2):
    """The last error lines of a pathfarm log (its warnings when it has none), without
    their time stamps."""
    found = {"error": [], "warning": []}
    for line in text.splitlines():
        match = LOG_PREFIX.match(line)
        if match and match.group(1) in ("error", "critical"):
            found["error"].append(line[match.end():])
        elif match and match.group(1) == "warning":
            found["warning"].append(line[match.end():])
    messages = found["error"] or found["warning"]
    return "; ".join(messages[-lines:]) or (text.strip().splitlines() or ["no output"])[-1]


def read_text(path):
    try:
        with open(path, encoding="utf-8", errors="replace") as file:
            return file.read()
    except OSError:
        return ""


class Connection:
    """How the command-line client reaches a scheduler."""

    def __init__(self, executable, scheduler, token_file=""):
        self.executable = executable
        self.scheduler = scheduler
        self.token_file = token_file

    def command(self, *arguments):
        options = ["--scheduler", self.scheduler]
        if self.token_file:
            options += ["--token-file", os.path.abspath(bpy_path(self.token_file))]
        return [self.executable, *arguments, *options]

    def run(self, *arguments, timeout=120):
        try:
            done = subprocess.run(self.command(*arguments), capture_output=True, text=True, timeout=timeout)
        except subprocess.TimeoutExpired:
            raise FarmError(f"pathfarm {arguments[0]} did not answer within {timeout} s") from None
        if done.returncode != 0:
            raise FarmError(f"pathfarm {arguments[0]}: {last_error(done.stderr)}")
        return done.stdout


def bpy_path(path):
    """A path as Blender writes it ('//' is the .blend's folder), made absolute."""
    if path.startswith("//"):
        try:
            import bpy

            return bpy.path.abspath(path)
        except ImportError:
            return path[2:]
    return path


class LocalFarm:
    """A scheduler on a loopback port and worker processes, all stopped with Blender (the
    workers also by --parent, should Blender end without stopping them)."""

    def __init__(self, executable, folder, workers):
        self.executable, self.folder, self.workers = executable, folder, workers
        self.processes = []
        os.makedirs(os.path.join(folder, "logs"), exist_ok=True)
        self.token_file = os.path.join(folder, "token")
        with open(os.open(self.token_file, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600), "w") as token:
            token.write(secrets.token_hex(24))
        port_file = os.path.join(folder, "port")
        if os.path.exists(port_file):
            os.remove(port_file)
        self._start("scheduler", "--listen", "127.0.0.1:0", "--port-file", port_file,
                    "--db", os.path.join(folder, "farm.db"), "--store", os.path.join(folder, "chunks"),
                    "--token-file", self.token_file)
        port = self._wait_for(port_file)
        self.address = f"127.0.0.1:{port}"
        threads = max(1, (os.cpu_count() or 1) // workers)
        for index in range(workers):
            self._start("worker", "--scheduler", self.address, "--token-file", self.token_file,
                        "--cache", os.path.join(folder, f"worker{index}"), "--threads", str(threads),
                        "--parent", str(os.getpid()), "--name", f"blender-{index}", log=f"worker{index}")

    def _start(self, command, *arguments, log=None):
        log_path = os.path.join(self.folder, "logs", (log or command) + ".log")
        with open(log_path, "w") as output:
            process = subprocess.Popen([self.executable, command, *arguments], stdout=output,
                                       stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL)
        self.processes.append((process, log_path))

    def _wait_for(self, port_file, seconds=30):
        scheduler, log_path = self.processes[0]
        deadline = time.monotonic() + seconds
        while time.monotonic() < deadline:
            text = read_text(port_file).strip()
            if text.isdigit():
                return int(text)
            if scheduler.poll() is not None:
                self.stop()
                raise FarmError(f"the local scheduler did not start: {last_error(read_text(log_path))}")
            time.sleep(0.05)
        self.stop()
        raise FarmError(f"the local scheduler did not start within {seconds} s")

    def alive(self):
        return bool(self.processes) and all(process.poll() is None for process, _ in self.processes)

    def connection(self):
        return Connection(self.executable, self.address, self.token_file)

    def stop(self):
        for process, _ in self.processes:
            if process.poll() is None:
                process.terminate()
        for process, _ in self.processes:
            try:
                process.wait(timeout=10)
            except subprocess.TimeoutExpired:
                process.kill()
                process.wait()
        self.processes = []


_local_farm = None


def local_farm(executable, folder, workers):
    """The running local farm, started (again) when there is none or its settings changed."""
    global _local_farm
    wanted = (executable, folder, workers)
    if _local_farm and _local_farm.alive() and (_local_farm.executable, _local_farm.folder, _local_farm.workers) == wanted:
        return _local_farm
    stop_local_farm()
    _local_farm = LocalFarm(*wanted)
    return _local_farm


def stop_local_farm():
    global _local_farm
    if _local_farm:
        _local_farm.stop()
        _local_farm = None


class ShotJob:
    """One shot: submitted (the pipeline probe of `auto` runs then), watched, and its frames
    and report fetched into `folder/frames`. poll() never blocks for long."""

    def __init__(self, connection, shot_file, folder):
        self.connection, self.shot_file, self.folder = connection, shot_file, folder
        self.frames_folder = os.path.join(folder, "frames")
        self.state, self.message, self.progress, self.shot_id = "submitting", "submitting", 0.0, 0
        self.logs = os.path.join(folder, "logs")
        os.makedirs(self.logs, exist_ok=True)
        self.process = self._spawn("submit", "submit", shot_file)

    def _spawn(self, log, *arguments):
        self.log_path = os.path.join(self.logs, log + ".log")
        with open(self.log_path, "w") as errors:
            return subprocess.Popen(self.connection.command(*arguments), stdout=subprocess.PIPE,
                                    stderr=errors, stdin=subprocess.DEVNULL, text=True)

    def finished(self):
        return self.state in ("done", "failed", "cancelled")

    def poll(self):
        if self.finished() or self.process.poll() is None:
            if self.state == "rendering":
                self._read_progress()
            return self.state
        output = self.process.stdout.read()
        if self.process.returncode != 0:
            self._fail("submit" if self.state == "submitting" else "render")
        elif self.state == "submitting":
            self.shot_id = int(output.split()[-1])
            self.state, self.message = "rendering", f"shot {self.shot_id} queued"
            self.process = self._spawn("watch", "watch", str(self.shot_id))
        else:
            self._fetch()
        return self.state

    def _read_progress(self):
        matches = PROGRESS.findall(read_text(self.log_path))
        if matches:
            _, done, total = matches[-1]
            self.progress = int(done) / max(1, int(total))
            self.message = f"shot {self.shot_id}: {done}/{total} tasks"

    def _fail(self, stage):
        self.state = "failed"
        self.message = f"{stage} failed: {last_error(read_text(self.log_path))}"

    def _fetch(self):
        self.message = "fetching frames"
        try:
            self.connection.run("fetch", str(self.shot_id), "--out", self.frames_folder, "--beauty", timeout=600)
            self.connection.run("report", str(self.shot_id), "--out", self.frames_folder)
        except FarmError as error:
            self.state, self.message = "failed", str(error)
            return
        self.state, self.progress = "done", 1.0
        self.message = f"shot {self.shot_id} done: {len(self.frames())} frames"

    def frames(self):
        """The beauty copies Blender reads (frames/beauty/); the full frames are in frames/."""
        beauty = os.path.join(self.frames_folder, "beauty")
        if not os.path.isdir(beauty):
            return []
        return sorted(os.path.join(beauty, name) for name in os.listdir(beauty)
                      if name.startswith("frame_") and name.endswith(".exr"))

    def cancel(self):
        if self.finished():
            return
        if self.state == "submitting":
            self.process.terminate()
        else:
            self.connection.run("cancel", str(self.shot_id))
            self.process.terminate()
        self.process.wait()
        self.state, self.message = "cancelled", f"shot {self.shot_id or '(not queued)'} cancelled"
