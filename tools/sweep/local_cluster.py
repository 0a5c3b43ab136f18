"""A dask.distributed scheduler and N single-thread workers on 127.0.0.1, as separate processes
(the same `dask scheduler` / `dask worker` commands a user runs on real machines), for the cluster
test and the sweep benchmark. Every process started here is stopped when the context ends.
"""
import contextlib
import os
import signal
import socket
import subprocess
import time


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class LocalCluster:
    def __init__(self, workdir, n_workers=2, timeout_s=60.0):
        self.workdir = workdir
        self.n_workers = n_workers
        self.timeout_s = timeout_s
        self.procs = []
        self.client = None
        self.address = None
        self.worker_pids = {}

    def start(self, args, log):
        """Starts a process in its own session (so it and its children can be killed together)."""
        p = subprocess.Popen(args, stdout=open(os.path.join(self.workdir, log), "w"), stderr=subprocess.STDOUT,
                             start_new_session=True)
        self.procs.append(p)
        return p

    def __enter__(self):
        from distributed import Client

        os.makedirs(self.workdir, exist_ok=True)
        port = free_port()
        self.address = f"tcp://127.0.0.1:{port}"
        self.start(["dask", "scheduler", "--host", "127.0.0.1", "--port", str(port), "--no-dashboard"],
                   "scheduler.log")
        for i in range(self.n_workers):
            self.start(["dask", "worker", self.address, "--nthreads", "1", "--nworkers", "1", "--no-dashboard",
                        "--no-nanny", "--name", f"w{i}"], f"worker{i}.log")
        t_end = time.monotonic() + self.timeout_s
        while self.client is None and time.monotonic() < t_end:
            try:
                self.client = Client(self.address, timeout="2s")
            except OSError:
                time.sleep(0.2)
        if self.client is None:
            self.__exit__(None, None, None)
            raise RuntimeError(f"dask scheduler did not come up at {self.address}")
        self.client.wait_for_workers(self.n_workers, timeout=max(1.0, t_end - time.monotonic()))
        self.worker_pids = self.client.run(os.getpid)  # worker address -> process id
        return self

    def __exit__(self, *exc):
        if self.client is not None:
            with contextlib.suppress(Exception):
                self.client.close()
        for p in self.procs:
            if p.poll() is None:
                try:
                    os.killpg(p.pid, signal.SIGKILL)
                except (ProcessLookupError, PermissionError):
                    p.kill()
            with contextlib.suppress(subprocess.TimeoutExpired):
                p.wait(timeout=10)
        return False
