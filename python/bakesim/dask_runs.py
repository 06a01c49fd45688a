"""The runs of a `bakesim sweep` on a dask.distributed cluster.

`bakesim sweep` keeps everything a sweep owns (its directory, marker and
lock, which runs to keep, resume or start, progress, the table and plots) and
hands each run, a `bakesim run ...` command line, to this helper, which runs
it as a task on a Dask worker:

    /usr/bin/python3 -m bakesim.dask_runs --scheduler local --workers 2

One JSON object per line on stdin, one per line on stdout:

    in:  {"start": 3, "argv": ["/usr/bin/bakesim", "run", ...], "log": "/abs/logs/3.txt", "cwd": "/abs"}
         {"signal": 15}          every running command gets this signal once (it checkpoints and stops)
    out: {"ready": true, "slots": 2, "scheduler": "inproc://..."}   first line, once connected
         {"unavailable": "No module named 'distributed'"}          instead, and exit status 3
         {"finished": 3, "returncode": 0}                          negative: killed by that signal
         {"finished": 3, "error": "..."}                           the task itself failed (worker lost, ...)

End of input: any command still running gets SIGTERM, and the helper exits
when every task has come back. A worker on another machine runs the command
in `cwd` with the paths it was given: the sweep directory, the scene and the
bakesim executable must be at the same paths there (a shared file system,
docs/python.md).
"""

import argparse
import json
import os
import queue
import signal
import subprocess
import sys
import threading
import uuid


def _die_with_parent():
    """In the child before exec: SIGTERM when the worker thread that started it goes (Linux prctl)."""
    try:
        import ctypes
        ctypes.CDLL(None).prctl(1, signal.SIGTERM)  # PR_SET_PDEATHSIG
    except Exception:
        pass


def run_command(argv, log, cwd, stop_name):
    """One run, on a Dask worker: the command with its output into `log`; the
    stop variable's signal is passed on once. Returns the return code."""
    from distributed import Variable

    stop = Variable(stop_name)
    with open(log, "wb") as out:
        child = subprocess.Popen(argv, stdout=out, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL, cwd=cwd,
                                 start_new_session=True, preexec_fn=_die_with_parent)
    sent = False
    while True:
        try:
            return child.wait(timeout=0.5)  # the scheduler asked twice a second per run, not more
        except subprocess.TimeoutExpired:
            pass
        if not sent:
            try:
                sig = int(stop.get(timeout=10) or 0)
            except Exception:
                sig = 0
            if sig:
                child.send_signal(sig)
                sent = True


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python3 -m bakesim.dask_runs", description=__doc__.split("\n\n")[0])
    parser.add_argument("--scheduler", default="local", help="'local' (a LocalCluster here) or a scheduler's address")
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 1,
                        help="runs at a time on the LocalCluster (one worker thread each)")
    args = parser.parse_args(argv)
    out_lock = threading.Lock()

    def send(message):
        with out_lock:
            sys.stdout.write(json.dumps(message) + "\n")
            sys.stdout.flush()

    try:
        import dask.distributed as dd
    except ImportError as e:
        send({"unavailable": str(e)})
        return 3
    # The sweep passes its signals on as {"signal": N}; the helper itself
    # only ends when its input does.
    for sig in (signal.SIGINT, signal.SIGHUP):
        signal.signal(sig, signal.SIG_IGN)

    cluster = None
    if args.scheduler == "local":
        # Each task waits on a `bakesim run` process: worker threads in this
        # process are enough, and start in a second.
        cluster = dd.LocalCluster(n_workers=1, threads_per_worker=max(1, args.workers), processes=False,
                                  dashboard_address=None)
        client = dd.Client(cluster)
    else:
        client = dd.Client(args.scheduler, timeout=30)
    stop = dd.Variable(f"bakesim-sweep-stop-{uuid.uuid4().hex}", client=client)
    stop.set(0)
    slots = sum(w.get("nthreads", 1) for w in client.scheduler_info()["workers"].values())
    send({"ready": True, "slots": int(slots), "scheduler": str(client.scheduler.address)})

    done = queue.Queue()
    pending = {}
    lock = threading.Lock()
    stopped = [False]

    def read_input():
        for line in sys.stdin:
            line = line.strip()
            if not line:
                continue
            message = json.loads(line)
            if "start" in message:
                future = client.submit(run_command, message["argv"], message["log"], message.get("cwd"), stop.name,
                                       key=f"bakesim-run-{uuid.uuid4().hex}", pure=False)
                with lock:
                    pending[future.key] = (message["start"], future)
                future.add_done_callback(done.put)
            elif "signal" in message and not stopped[0]:
                stopped[0] = True
                stop.set(int(message["signal"]))
        if not stopped[0]:
            stopped[0] = True
            stop.set(int(signal.SIGTERM))
        done.put(None)

    threading.Thread(target=read_input, daemon=True).start()
    input_ended = False
    while True:
        with lock:
            if input_ended and not pending:
                break
        item = done.get()
        if item is None:
            input_ended = True
            continue
        with lock:
            run, future = pending.pop(item.key)
        try:
            send({"finished": run, "returncode": int(future.result())})
        except Exception as e:  # the task failed: the worker was lost, the command could not start, ...
            send({"finished": run, "error": f"{type(e).__name__}: {e}"})
    client.close()
    if cluster is not None:
        cluster.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
