"""tsm-contact for Python: large-displacement contact of plane frames by the Tangent Stiffness
Method, on the same Rust library as the `tsm-contact` program.

    import tsm_contact as tc
    scene = tc.Scene.builtin("example_3_2")
    history = tc.solve(scene, on_increment=lambda r: print(r["increment"]))
    history.positions      # numpy array [increments, nodes, 3]: x, y, rotation
    tc.check(history)      # the independent audit: [] when nothing is wrong

`Scene` reads and validates scene files (RON) and dicts with located errors (`SceneError`
carries `file`, `line`, `field` and `message`); `solve` runs in Rust without holding the GIL
and returns a `History` (the CLI's `solve --json` format, with numpy arrays); `check` audits a
history with code that shares nothing with the solver; `figure` draws a state as PNG or SVG.
Scenes and histories pickle, so that a distributed engine (Dask) can ship them.
"""

import json as _json
import os as _os

import numpy as _np

from . import _native
from ._native import SceneError, SolveError

__all__ = [
    "Scene",
    "History",
    "SceneError",
    "SolveError",
    "solve",
    "check",
    "figure",
    "builtin_names",
]


def builtin_names():
    """The names of the built-in scenes."""
    return list(_native.builtin_names())


class Scene:
    """A validated scene: bodies, sections, supports, contacts, the drive and the steps."""

    __slots__ = ("_s",)

    def __init__(self, native):
        self._s = native

    @classmethod
    def from_file(cls, path):
        """Read and validate the RON scene file at `path` (raises `SceneError`)."""
        return cls(_native.Scene.from_file(_os.fspath(path)))

    @classmethod
    def from_text(cls, text, origin="<text>"):
        """Validate RON scene text; errors name `origin` as the file."""
        return cls(_native.Scene.from_text(text, origin))

    @classmethod
    def from_dict(cls, d, origin="<dict>"):
        """Validate a scene given as a dict of the scene file's fields (as in the RON file:
        points as [x, y] lists, enum values such as "V" or "BernoulliEuler" as strings)."""
        return cls(_native.Scene.from_json(_json.dumps(d), origin))

    @classmethod
    def builtin(cls, name):
        """A built-in scene by name (`builtin_names()` lists them)."""
        return cls(_native.Scene.builtin(name))

    def to_dict(self):
        """The scene file's fields as a dict, which `from_dict` takes back (edit it to vary a
        scene: a mesh, a friction coefficient, a drive)."""
        return _json.loads(self._s.to_json())

    def to_ron(self):
        """The scene as RON text that `from_text` reads back to the same scene."""
        return self._s.to_ron()

    @property
    def name(self):
        """The scene's name."""
        return self._s.name

    @property
    def steps(self):
        """The steps a run makes by default."""
        return self._s.steps

    @property
    def node_ids(self):
        """The node ids, in the order of a history's node arrays."""
        return list(self._s.node_ids)

    @property
    def formulation(self):
        """The element formulation: "Timoshenko" or "BernoulliEuler"."""
        return self._s.formulation

    def __reduce__(self):
        return (Scene.from_text, (self.to_ron(), self.name))

    def __repr__(self):
        return f"Scene({self.name!r}, {len(self.node_ids)} nodes, {self.steps} steps)"


def _array(native, name):
    raw, shape = native.array(name)
    return _np.frombuffer(raw, dtype="<f8").reshape(shape)


class History:
    """A run: every accepted increment and event, and the error it stopped on (None: it made
    every step asked for). Arrays are numpy arrays; `scene` is the Scene it ran when it came
    from `solve` (None for a history loaded from a file)."""

    __slots__ = ("_h", "scene", "_cache")

    def __init__(self, native, scene=None):
        self._h = native
        self.scene = scene
        self._cache = {}

    @classmethod
    def load(cls, path, scene=None):
        """The history file at `path`, as `tsm-contact solve --json` writes it."""
        return cls(_native.History.load(_os.fspath(path)), scene)

    @classmethod
    def from_json(cls, text, scene=None):
        """A history from its JSON text."""
        return cls(_native.History.from_json(text), scene)

    def to_json(self):
        """The history as JSON text, as `tsm-contact solve --json` writes it."""
        return self._h.to_json()

    def save(self, path):
        """Write the history as JSON (atomically), readable by `tsm-contact check` and the app."""
        self._h.save(_os.fspath(path))

    def _get(self, name, make):
        if name not in self._cache:
            self._cache[name] = make()
        return self._cache[name]

    @property
    def scene_name(self):
        """The name of the scene that ran."""
        return self._h.scene

    @property
    def error(self):
        """Why the run stopped early, or None."""
        return self._h.error

    @property
    def completed(self):
        """Whether the run made every step it was asked for."""
        return self._h.error is None

    @property
    def node_ids(self):
        """User ids of the nodes, in the order of `positions`."""
        return _np.asarray(self._h.node_ids, dtype=_np.int64)

    @property
    def positions(self):
        """Node states [increments, nodes, 3]: x, y and rotation."""
        return self._get("positions", lambda: _array(self._h, "positions"))

    @property
    def prescribed(self):
        """The prescribed displacements [increments, prescribed dofs]."""
        return self._get("prescribed", lambda: _array(self._h, "prescribed"))

    @property
    def load_factors(self):
        """The load factor of each increment."""
        return self._get("load_factor", lambda: _array(self._h, "load_factor"))

    @property
    def increments(self):
        """The increment number of each record."""
        return self._get("increment", lambda: _array(self._h, "increment").astype(_np.int64))

    @property
    def iterations(self):
        """Newton iterations of each accepted increment."""
        return self._get("iterations", lambda: _array(self._h, "iterations").astype(_np.int64))

    @property
    def relative_residuals(self):
        """The relative residual each increment was accepted at."""
        return self._get("relative_residual", lambda: _array(self._h, "relative_residual"))

    @property
    def statuses(self):
        """How each increment met the equilibrium test: "converged" or "roundoff"."""
        return list(self._h.statuses)

    def _table(self, name):
        def make():
            out = {}
            for key, col in self._h.table(name).items():
                if isinstance(col, tuple):
                    raw, n = col
                    a = _np.frombuffer(raw, dtype="<f8", count=n)
                    if key in ("increment", "node", "element", "place"):
                        a = a.astype(_np.int64)
                    out[key] = a
                else:
                    out[key] = _np.asarray(col, dtype=object)
            return out

        return self._get("table " + name, make)

    @property
    def contacts(self):
        """Node-on-beam contacts of every increment as a dict of equal-length arrays (one row
        per contact and increment): increment, node, element, place, body, xi, force, pressure,
        tangential. `pandas.DataFrame(history.contacts)` makes a table of it."""
        return self._table("contacts")

    @property
    def obstacle_contacts(self):
        """Contacts with rigid obstacles, a row per contact and increment: increment, node,
        obstacle, force, gap, x, y, tangential."""
        return self._table("obstacle_contacts")

    @property
    def reactions(self):
        """Support reactions, a row per reaction and increment: increment, node, dof, value."""
        return self._table("reactions")

    @property
    def events(self):
        """Every event (cut-backs and contact changes) as dicts, in order."""
        return self._get("events", lambda: _json.loads(self._h.events_json()))

    def record(self, k):
        """Record `k` (0-based) as a dict, as in the JSON file."""
        return _json.loads(self._h.record_json(k))

    def __len__(self):
        return len(self._h)

    def __reduce__(self):
        return (History.from_json, (self.to_json(), self.scene))

    def __repr__(self):
        end = "completed" if self.completed else f"stopped: {self.error}"
        return f"History({self.scene_name!r}, {len(self)} increments, {end})"


def solve(scene, steps=None, on_increment=None):
    """Run `scene` for `steps` steps (default: the scene's) and return its History.

    The solve runs in Rust without holding the GIL. `on_increment(record)` is called with each
    accepted increment's record (a dict, as in the JSON history); returning False stops the run
    there (the history's `error` then says so). A run that fails returns the history so far
    with `error` set; Ctrl-C stops the run
    at the next Newton iteration and raises KeyboardInterrupt. Raises `SolveError` if the
    solver cannot start (a mechanism, a node starting inside a body)."""
    callback = None
    if on_increment is not None:

        def callback(text):
            answer = on_increment(_json.loads(text))
            return answer is None or answer is not False

    native = _native.solve(scene._s, steps, callback)
    return History(native, scene)


def check(history):
    """The independent audit of `history` (code that shares nothing with the solver's own
    checks): a list of findings as dicts (increment, node, body, text); empty when it finds
    nothing wrong."""
    return [
        {"increment": i, "node": n, "body": b, "text": t}
        for (i, n, b, t) in _native.check(history._h)
    ]


def figure(scene_or_history, increment=None, path=None, *, scene=None, steps=None, diagram=None, size=(1600, 1000)):
    """Draw a state as the CLI's `figure` does, to `path` (.png or .svg).

    Given a History, draws its increment `increment` (default: the last; 0: the undeformed
    state); the history's scene is used unless `scene` is given (needed for a history loaded
    from a file). Given a Scene, solves `steps` steps (default: the scene's) and draws the last
    state. `diagram`: "N", "V" or "M"; `size`: a PNG's (width, height) in pixels."""
    if path is None:
        raise TypeError("figure() needs a path (.png or .svg)")
    if isinstance(scene_or_history, History):
        sc = scene or scene_or_history.scene
        if sc is None:
            raise ValueError(
                "this history was loaded from a file and carries no scene: pass scene=Scene.from_file(...)"
            )
        _native.figure(sc._s, _os.fspath(path), scene_or_history._h, increment, None, diagram, tuple(size))
    else:
        _native.figure(scene_or_history._s, _os.fspath(path), None, None, steps, diagram, tuple(size))
