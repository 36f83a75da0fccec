"""Files written whole or not at all, as isoatlas's own writers do: into .PID-0@HOST.partial.NAME beside
the target, then renamed over it (a worker killed mid-write leaves only the hidden partial, which the
next run of that subject on the same host removes)."""
import os
import re
import socket


def write_atomically(path, data, if_changed=False):
    """Writes `data` (bytes or str) to `path`; with if_changed, leaves a file of the same bytes as it
    is (so that a run that changes nothing touches nothing)."""
    if isinstance(data, str):
        data = data.encode("utf-8")
    if if_changed:
        try:
            with open(path, "rb") as f:
                if f.read() == data:
                    return False
        except OSError:
            pass
    temporary = os.path.join(os.path.dirname(path) or ".", f".{os.getpid()}-0@{_host()}.partial.{os.path.basename(path)}")
    try:
        with open(temporary, "wb") as f:
            f.write(data)
            f.flush()
            os.fsync(f.fileno())
        os.replace(temporary, path)
    finally:
        if os.path.exists(temporary):
            os.remove(temporary)
    return True


def _host():
    return socket.gethostname().replace("/", "_") or "localhost"


def _pid_is_gone(pid):
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return True
    except OSError:  # alive, another user's
        return False
    return False


def remove_partials(folder):
    """What a writer killed mid-file left in `folder` (isoatlas writes NAME through
    .PID-N@HOST.partial.NAME): this host's, whose process is gone. Another host's may be live (a
    cohort across hosts on a shared folder), and a live process's is being written."""
    pattern = re.compile(r"^\.(\d+)-\d+@(.+?)\.partial\.")
    for name in os.listdir(folder):
        match = pattern.match(name)
        if match and match.group(2) == _host() and _pid_is_gone(int(match.group(1))):
            try:
                os.remove(os.path.join(folder, name))
            except FileNotFoundError:
                pass
