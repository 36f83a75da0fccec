"""The cohort on Dask: subjects whose outputs are settled are skipped, the rest submitted one task each
to a local cluster of single-threaded worker processes (or to an existing scheduler), their reports
gathered as they finish, with one progress line over the subjects and a log line per stage."""
import logging
import os
import sys
import threading
import time

from . import subject as subjects_
from .manifest import InputError, parse_stages, read_config, read_manifest
from .table import row_of, write_index, write_table


class _Progress:
    """One line over the subjects: rewritten in place on a terminal, else printed as it changes.
    Dask's event handler says its lines from another thread, so each line goes out in one write under
    a lock (print writes the text and its end apart, and two threads' lines would interleave)."""

    def __init__(self, total, quiet):
        self.total, self.quiet, self.started = total, quiet, time.monotonic()
        self.tty = sys.stderr.isatty()
        self.lock = threading.Lock()

    def _write(self, text):
        with self.lock:
            sys.stderr.write(text)
            sys.stderr.flush()

    def line(self, done, failed, running):
        finished = done + failed
        left = self.total - finished
        elapsed = time.monotonic() - self.started
        eta = f", ETA {elapsed / finished * left:.0f} s" if finished and left else ""
        return f"cohort: {finished}/{self.total} subjects: {done} done, {failed} failed, {running} running{eta}"

    def show(self, done, failed, running):
        if self.quiet:
            return
        text = self.line(done, failed, running)
        self._write("\r" + text + "\033[K" if self.tty else text + "\n")

    def say(self, text):
        """A log line, above the progress line on a terminal."""
        if self.quiet:
            return
        self._write(("\r\033[K" if self.tty else "") + text + "\n")

    def end(self):
        if self.tty and not self.quiet:
            self._write("\n")


def _client(workers, scheduler, allowed_failures):
    """A Dask client: on the scheduler at `scheduler`, or on a new local cluster of `workers`
    single-threaded processes (the caller closes both)."""
    import dask
    from distributed import Client, LocalCluster

    if scheduler:
        try:
            return Client(scheduler, timeout="10s"), None
        except (OSError, TimeoutError) as e:
            raise InputError(f"--scheduler {scheduler}: no Dask scheduler answers there ({e})") from None
    dask.config.set({"distributed.scheduler.allowed-failures": allowed_failures})
    cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None,
                           silence_logs=logging.ERROR)
    return Client(cluster), cluster


def _gave_up(subject, digest, error):
    return {"id": subject.id, "hash": digest, "status": "failed", "error": error, "bad_input": False, "seconds": {}, "figures": {}}


def run_cohort(manifest, out_dir, workers=None, scheduler=None, stages="segment,extract,build,eval,render", config=None, quiet=False):
    """Runs the cohort; returns (rows of cohort.csv, whether it was stopped by Ctrl-C). Raises
    InputError, before any subject runs, for a bad manifest, config or option."""
    settings = read_config(config)
    subjects = read_manifest(manifest, settings)
    stage_list = parse_stages(stages)
    if workers is not None and workers < 1:
        raise InputError("--workers must be >= 1")
    if os.path.exists(out_dir) and not os.path.isdir(out_dir):
        raise InputError(f"--out {out_dir}: a file is there, not a folder")
    progress = _Progress(len(subjects), quiet)

    reports, todo, digests = {}, [], {}
    for s in subjects:
        digests[s.id] = subjects_.input_hash(s, settings, stage_list)
        earlier = subjects_.read_report(out_dir, s)
        if subjects_.is_settled(earlier, digests[s.id], out_dir, s, stage_list):
            reports[s.id] = earlier
        else:
            todo.append(s)
    if len(reports):
        progress.say(f"cohort: {len(reports)} of {len(subjects)} subjects already settled (same input and parameters): skipped")

    stopped = False
    if todo:
        stopped = _run_on_dask(todo, settings, stage_list, out_dir, digests, reports, progress,
                               workers or os.cpu_count() or 1, scheduler)
    progress.end()
    for s in todo:  # stopped: a subject may have finished after the last result was gathered
        if s.id not in reports:
            earlier = subjects_.read_report(out_dir, s)
            if earlier and earlier.get("hash") == digests[s.id]:
                reports[s.id] = earlier
    rows = [row_of(reports[s.id]) if s.id in reports else {"id": s.id, "status": "not run", "error": "stopped before it ran"}
            for s in subjects]
    os.makedirs(out_dir, exist_ok=True)  # only now: a scheduler that does not answer leaves nothing behind
    write_table(out_dir, rows)
    write_index(out_dir, rows)
    return rows, stopped


def _run_on_dask(todo, settings, stages, out_dir, digests, reports, progress, workers, scheduler):
    """Submits `todo`, fills `reports` as subjects finish; returns True when stopped by Ctrl-C."""
    from distributed import as_completed
    from distributed.scheduler import KilledWorker

    client, cluster = _client(workers, scheduler, settings["allowed_failures"])
    try:
        client.subscribe_topic(subjects_.LOG_TOPIC, _log_handler(progress))
        futures = {}
        for s in todo:
            future = client.submit(subjects_.run_subject, s, settings, stages, out_dir, digests[s.id], pure=False,
                                   key=f"isoatlas-cohort-{s.id}-{digests[s.id][:12]}")
            futures[future] = s
        slots = workers if cluster else max(1, len(client.scheduler_info().get("workers", {})))
        done = sum(r.get("status") == "done" for r in reports.values())
        failed = len(reports) - done
        pending = len(futures)
        progress.show(done, failed, min(slots, pending))
        try:
            for future in as_completed(futures):
                s = futures[future]
                try:
                    report = future.result()
                except KilledWorker:
                    report = _gave_up(s, digests[s.id], "the workers running it died more often than allowed_failures allows "
                                                         "(killed, or out of memory?); the next run tries it again")
                except Exception as e:  # noqa: BLE001 - a task that could not even start (pickling, import)
                    report = _gave_up(s, digests[s.id], f"{type(e).__name__}: {e}")
                reports[s.id] = report
                pending -= 1
                if report["status"] == "done":
                    done += 1
                else:
                    failed += 1
                    progress.say(f"cohort: {s.id}: failed: {report['error']}")
                progress.show(done, failed, min(slots, pending))
        except KeyboardInterrupt:
            progress.say(f"cohort: stopped by Ctrl-C with {pending} subjects not finished; run the same command again to go on")
            for future in futures:
                future.cancel()
            return True
    finally:
        _close(client, cluster)
    return False


def _log_handler(progress):
    """The workers' events as lines: each stage, and where each subject starts; a subject started a
    second time was lost with its worker (killed, out of memory) and is run again."""
    started = {}

    def say(event):
        message = event[1]
        if "started_on" not in message:
            progress.say(subjects_.format_log(message))
            return
        where = f"{message['started_on']} (pid {message['pid']})"
        earlier = started.get(message["id"])
        started[message["id"]] = where
        if earlier:
            progress.say(f"cohort: {message['id']}: started again on {where}: the worker that ran it, {earlier}, was lost")
        else:
            progress.say(f"cohort: {message['id']}: started on {where}")
    return say


def _close(client, cluster):
    """Closes the client and the local cluster, quietly, even after a Ctrl-C reached the workers."""
    logging.getLogger("distributed").setLevel(logging.CRITICAL)
    for closable in (client, cluster):
        if closable is not None:
            try:
                closable.close(timeout=10)
            except Exception:  # noqa: BLE001 - closing what may already be gone
                pass
