"""The live meter mode's runtime state per scene (not saved in the .blend): what is stale, what the last
reading saw, the one-line status the panel and the overlay print.

It lives with the properties because the ``live`` property's update callback (``props/meter.py``) marks
a scene stale when the mode is switched on, and properties import nothing above them; the mode itself
(the depsgraph handler and the timer that measure) is ``operators/live.py``."""

import time

class LiveState:
    """What the live mode knows about one scene."""

    def __init__(self):
        self.dirty_all = True          # first sight of a live scene: measure everything
        self.dirty_meters = set()      # names of meters that moved
        self.changed_at = 0.0
        self.poses = {}                # meter name -> pose signature of its last live reading
        self.settings = None           # the scene settings signature at the last live reading
        self.refine = []               # names of meters whose reading still needs refining
        self.measured_at = 0.0
        self.status = "Live: waiting for the first reading"
        self.preview_seconds = None    # wall time of the last preview measurement
        self.measurements = 0          # live measurements done (tests and the benchmark count them)

    @property
    def dirty(self):
        return self.dirty_all or bool(self.dirty_meters)


_states = {}


def key(scene):
    return scene.as_pointer()


def state(scene):
    st = _states.get(key(scene))
    if st is None:
        st = _states[key(scene)] = LiveState()
        st.changed_at = time.perf_counter()
    return st


def status(scene):
    st = _states.get(key(scene))
    return st.status if st is not None else ""


def reset():
    _states.clear()


def mark_dirty(scene, meters=None, now=None):
    """Make every live meter of ``scene`` (or only the named ``meters``) stale."""
    st = state(scene)
    if meters is None:
        st.dirty_all = True
    else:
        st.dirty_meters.update(meters)
    st.changed_at = time.perf_counter() if now is None else now


def forget_all_but(keys):
    """Forget the state of every scene whose :func:`key` is not in ``keys`` (live turned off, scene gone)."""
    for k in set(_states) - set(keys):
        del _states[k]
