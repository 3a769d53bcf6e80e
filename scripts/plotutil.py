"""Helpers shared by the plotting scripts (imported from the scripts' own folder)."""
import os


def save_atomically(fig, out, **kwargs):
    """Draw into a temporary beside `out` (the name hemicontact uses, ".NAME.partial") and rename
    it into place, so an interrupted run never leaves half a picture under the final name."""
    tmp = os.path.join(os.path.dirname(out) or ".", "." + os.path.basename(out) + ".partial")
    try:
        fig.savefig(tmp, format="png", **kwargs)
        os.replace(tmp, out)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)
