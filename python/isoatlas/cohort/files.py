"""Files written whole or not at all, as isoatlas's own writers do: into .PID.partial.NAME beside the
target, then renamed over it (a worker killed mid-write leaves only the hidden partial, which the next
run of that subject removes)."""
import os


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
    temporary = os.path.join(os.path.dirname(path) or ".", f".{os.getpid()}.partial.{os.path.basename(path)}")
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


def remove_partials(folder):
    """What a writer killed mid-file left in `folder` (isoatlas writes NAME through .PID-N.partial.NAME)."""
    for name in os.listdir(folder):
        if name.startswith(".") and ".partial." in name:
            os.remove(os.path.join(folder, name))
