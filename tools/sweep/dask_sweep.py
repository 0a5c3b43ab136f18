#!/usr/bin/python3
"""The Dask path of `dtc-sil sweep --dask tcp://HOST:PORT` (not meant to be called by hand).

dtc-sil has already checked the sweep, expanded the plan and removed the runs that are done; it
writes a job file and calls this script, which
  * connects to the dask.distributed scheduler (an unreachable one is refused before any run),
  * cuts the pending run indices into chunks and submits one task per chunk: the task runs
    `dtc-sil sweep-exec` on the worker with the chunk on its standard input and returns the rows it
    prints (the worker needs the dtc-sil binary at the same path: a shared folder, or the same
    install on every worker; see docs/sil.md),
  * appends every finished chunk's rows to DIR/rows.jsonl at once, so an interrupted sweep keeps
    them and `--resume` runs only the rest.
A worker that dies mid-task loses nothing: the scheduler re-runs its tasks on another worker, and a
task that fails is retried (retries=3). dtc-sil then writes summary.csv from rows.jsonl with the
same code as a local sweep, so the summaries are identical row for row.

Exit status: 0 done, 1 scheduler unreachable or bad job file, 2 a chunk failed after its retries.
"""
import json
import math
import subprocess
import sys
import time


def run_chunk(exe, spec, runs, timeout_s):
    """Runs on a worker: one dtc-sil process for the chunk; returns its rows (JSON texts)."""
    chunk = json.dumps({"spec": spec, "runs": runs, "timeout_s": timeout_s})
    done = subprocess.run([exe, "sweep-exec"], input=chunk, capture_output=True, text=True, check=False)
    if done.returncode != 0:
        raise RuntimeError(f"dtc-sil sweep-exec exited {done.returncode}: {done.stderr.strip()[:500]}")
    rows = [line for line in done.stdout.splitlines() if line.strip()]
    if len(rows) != len(runs):
        raise RuntimeError(f"dtc-sil sweep-exec returned {len(rows)} rows for {len(runs)} runs")
    return rows


def main(job_path):
    with open(job_path, encoding="utf-8") as f:
        job = json.load(f)
    try:
        from distributed import Client, as_completed
    except ImportError:
        print("dtc-sil sweep: --dask needs python3-distributed (Debian); tools/setup.sh installs it", file=sys.stderr)
        return 1
    address = job["scheduler"]
    try:
        client = Client(address, timeout="10s")
    except Exception as e:  # noqa: BLE001 - any failure to connect is the same answer to the user
        print(f"dtc-sil sweep: --dask {address}: cannot reach the scheduler ({e})", file=sys.stderr)
        return 1
    pending = job["pending"]
    if not pending:
        client.close()
        return 0
    chunk = int(job.get("chunk") or 0)
    if chunk <= 0:
        workers = max(1, sum(w.get("nthreads", 1) for w in client.scheduler_info()["workers"].values()))
        chunk = max(1, min(50, math.ceil(len(pending) / (4 * workers))))
    chunks = [pending[i:i + chunk] for i in range(0, len(pending), chunk)]
    futures = [
        client.submit(run_chunk, job["exe"], job["spec"], c, job["timeout_s"], retries=3, pure=False,
                      key=f"dtc-sil-sweep-{c[0]}-{time.time_ns()}")
        for c in chunks
    ]
    done_runs, failed, t0 = 0, 0, time.monotonic()
    with open(job["rows"], "a", encoding="utf-8") as rows:
        for fut in as_completed(futures):
            try:
                lines = fut.result()
            except Exception as e:  # noqa: BLE001 - reported, the others go on
                failed += 1
                print(f"dtc-sil sweep: a chunk failed after its retries: {e}", file=sys.stderr)
                continue
            rows.write("".join(line + "\n" for line in lines))
            rows.flush()
            done_runs += len(lines)
            if job.get("progress"):
                rate = done_runs / max(1e-9, time.monotonic() - t0)
                eta = (len(pending) - done_runs) / rate if rate > 0 else 0.0
                print(f"\rsweep (dask): {done_runs}/{len(pending)} runs, {rate:.1f} runs/s, ETA {eta:.0f} s   ",
                      end="", file=sys.stderr, flush=True)
    if job.get("progress"):
        print(file=sys.stderr)
    client.close()
    return 2 if failed else 0


if __name__ == "__main__":
    if len(sys.argv) != 2:
        print("usage: dask_sweep.py JOB.json (written by dtc-sil sweep --dask)", file=sys.stderr)
        sys.exit(1)
    sys.exit(main(sys.argv[1]))
