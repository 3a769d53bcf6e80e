"""Helpers shared by the plotting scripts (imported from the scripts' own folder)."""
import os


def save_atomically(fig, out, **kwargs):
    """Draw into a temporary beside `out` (the name hemicontact uses, ".NAME.partial") and rename
    it into place, so an interrupted run never leaves half a picture under the final name."""
    tmp = os.path.join(os.path.dirname(out) or ".", "." + os.path.basename(out) + ".partial")
    # Created exclusively and never through a link, as hemicontact's own temporaries are: a name
    # planted there fails the picture instead of being written through, and is left alone.
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW | os.O_CLOEXEC, 0o666)
    try:
        with os.fdopen(fd, "wb") as f:
            fig.savefig(f, format="png", **kwargs)
        os.replace(tmp, out)
    except BaseException:
        if os.path.lexists(tmp):
            os.remove(tmp)
        raise
