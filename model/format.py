"""The blobtree-1 JSON format: load with full validation, save canonically.

Validation walks the document iteratively (no recursion), so hostile nesting cannot
overflow the stack; every error names the node's path from the root, e.g.
``root.children[3].radius: must be > 0, got -1``. Nothing is half-loaded: either a
complete :class:`Model` comes back or :class:`ModelError` is raised.
"""
import hashlib
import json
import math

from . import nodes as N

FORMAT = "blobtree-1"
MAX_NODES = 200_000        # far above the papers' 1497-node shell
MAX_DEPTH = 256            # nesting depth of the node tree
MAX_BYTES = 256 * 2**20    # size of a model file
MAX_ABS = 1e9              # largest magnitude accepted for any coordinate or length
MIN_LENGTH = 1e-9          # smallest radius, scale factor, normal length and non-zero bend rate:
                           # their squares and inverses stay far from underflow and overflow

_COMMON = {"type", "name"}
SPEC = {
    # type: {key: (kind, required)}
    "point": {"center": ("vec", True), "radius": ("pos", True), "strength": ("num", False)},
    "segment": {"a": ("vec", True), "b": ("vec", True), "radius": ("pos", True),
                "strength": ("num", False)},
    "circle": {"center": ("vec", True), "normal": ("dir", True), "circle_radius": ("pos", True),
               "radius": ("pos", True), "strength": ("num", False)},
    "disc": {"center": ("vec", True), "normal": ("dir", True), "disc_radius": ("pos", True),
             "radius": ("pos", True), "strength": ("num", False)},
    "box": {"center": ("vec", True), "half_size": ("nonneg_vec", True), "radius": ("pos", True),
            "strength": ("num", False)},
    "blend": {"children": ("children", True)},
    "ricci": {"children": ("children", True), "n": ("ricci_n", True)},
    "union": {"children": ("children", True)},
    "intersection": {"children": ("children", True)},
    "difference": {"children": ("children2", True)},
    "transform": {"child": ("child", True), "translate": ("vec", False), "rotate": ("angles", False),
                  "scale": ("scale", False)},
    "twist": {"child": ("child", True), "rate": ("num", True)},
    "taper": {"child": ("child", True), "rate": ("num", True)},
    "bend": {"child": ("child", True), "rate": ("bend_rate", True)},
}
_DEFAULTS = {"strength": 1.0, "translate": (0.0, 0.0, 0.0), "rotate": (0.0, 0.0, 0.0),
             "scale": (1.0, 1.0, 1.0)}


class ModelError(ValueError):
    """A model document (or node tree) breaks a rule; the message names where."""


def _is_num(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool)


class _NonFinite:
    """A NaN or Infinity literal, kept as it was written until validation names its node."""

    def __init__(self, literal):
        self.literal = literal


def _number(v, path):
    if isinstance(v, _NonFinite):
        raise ModelError(f"{path}: must be a finite number, got the literal {v.literal}")
    if not _is_num(v):
        raise ModelError(f"{path}: must be a number, got {_describe(v)}")
    try:
        f = float(v)
    except OverflowError:
        raise ModelError(f"{path}: number too large") from None
    if not math.isfinite(f):
        raise ModelError(f"{path}: must be finite, got {f}")
    if abs(f) > MAX_ABS:
        raise ModelError(f"{path}: magnitude must be at most {MAX_ABS:g}, got {f:g}")
    return f


def _vector(v, path):
    if not isinstance(v, list) or len(v) != 3:
        raise ModelError(f"{path}: must be a list of 3 numbers, got {_describe(v)}")
    return tuple(_number(x, f"{path}[{i}]") for i, x in enumerate(v))


def _describe(v):
    if isinstance(v, _NonFinite):
        return f"the literal {v.literal}"
    if isinstance(v, bool):
        return "a boolean"
    if v is None:
        return "null"
    if isinstance(v, str):
        return f"the string {v[:40]!r}"
    if isinstance(v, list):
        return f"a list of {len(v)}"
    if isinstance(v, dict):
        return "an object"
    return repr(v)[:40]


def _check_value(kind, v, path):
    if kind == "num":
        return _number(v, path)
    if kind == "pos":
        f = _number(v, path)
        if not f > 0:
            raise ModelError(f"{path}: must be > 0, got {f:g}")
        if f < MIN_LENGTH:
            raise ModelError(f"{path}: must be at least {MIN_LENGTH:g}, got {f:g}")
        return f
    if kind == "ricci_n":
        f = _number(v, path)
        if not f >= 1:
            raise ModelError(f"{path}: must be >= 1, got {f:g}")
        return f
    if kind == "bend_rate":
        f = _number(v, path)
        if f != 0 and abs(f) < MIN_LENGTH:
            raise ModelError(f"{path}: must be 0 or at least {MIN_LENGTH:g} in size (a bend radius of at most "
                             f"{1 / MIN_LENGTH:g}), got {f:g}")
        return f
    if kind in ("vec", "angles"):
        return _vector(v, path)
    if kind == "nonneg_vec":
        t = _vector(v, path)
        for i, x in enumerate(t):
            if x < 0:
                raise ModelError(f"{path}[{i}]: must be >= 0, got {x:g}")
        return t
    if kind == "dir":
        t = _vector(v, path)
        if t == (0.0, 0.0, 0.0):
            raise ModelError(f"{path}: must not be the zero vector")
        if math.hypot(*t) < MIN_LENGTH:
            raise ModelError(f"{path}: must be at least {MIN_LENGTH:g} long, got {math.hypot(*t):g}")
        return t
    if kind == "scale":
        t = _vector(v, path)
        for i, x in enumerate(t):
            if x == 0:
                raise ModelError(f"{path}[{i}]: must not be 0 (the transform must be invertible)")
            if abs(x) < MIN_LENGTH:
                raise ModelError(f"{path}[{i}]: must be at least {MIN_LENGTH:g} in size, got {x:g}")
        return t
    raise AssertionError(kind)


def from_dict(doc):
    """Validate a parsed JSON document and build a :class:`~.nodes.Model`."""
    if not isinstance(doc, dict):
        raise ModelError(f"document: must be a JSON object, got {_describe(doc)}")
    allowed = {"format", "name", "iso", "root"}
    for k in doc:
        if k not in allowed:
            raise ModelError(f"document: unknown key {k!r} (allowed: format, name, iso, root)")
    if "format" not in doc:
        raise ModelError("document.format: missing (must be \"blobtree-1\")")
    if doc["format"] != FORMAT:
        raise ModelError(f"document.format: must be \"{FORMAT}\", got {_describe(doc['format'])}")
    name = doc.get("name", "model")
    if not isinstance(name, str) or not name.strip():
        raise ModelError(f"document.name: must be a non-empty string, got {_describe(name)}")
    iso = _number(doc.get("iso", 0.5), "document.iso")
    if not iso > 0:
        raise ModelError(f"document.iso: must be > 0, got {iso:g}")
    if "root" not in doc:
        raise ModelError("document.root: missing")
    return N.Model(root=_build_tree(doc["root"]), name=name, iso=iso)


def _build_tree(root_doc):
    # Pass 1 (pre-order, iterative): validate each node's own keys, record children.
    order = []          # (path, type, fields, child_slots)
    stack = [(root_doc, "root", 0)]
    while stack:
        d, path, depth = stack.pop()
        if depth > MAX_DEPTH:
            raise ModelError(f"{path}: nesting deeper than {MAX_DEPTH} levels")
        if len(order) >= MAX_NODES:
            raise ModelError(f"{path}: model has more than {MAX_NODES} nodes")
        if not isinstance(d, dict):
            raise ModelError(f"{path}: must be a node object, got {_describe(d)}")
        t = d.get("type")
        if not isinstance(t, str) or t not in SPEC:
            raise ModelError(f"{path}.type: must be one of {', '.join(SPEC)}, got {_describe(t)}")
        spec = SPEC[t]
        for k in d:
            if k not in spec and k not in _COMMON:
                raise ModelError(f"{path}: unknown key {k!r} for a {t} node "
                                 f"(allowed: {', '.join(['type', 'name', *spec])})")
        fields = {}
        if "name" in d:
            if not isinstance(d["name"], str):
                raise ModelError(f"{path}.name: must be a string, got {_describe(d['name'])}")
            fields["name"] = d["name"]
        kids = []
        for k, (kind, required) in spec.items():
            if k not in d:
                if required:
                    raise ModelError(f"{path}.{k}: missing (a {t} node needs it)")
                continue
            v = d[k]
            if kind in ("children", "children2"):
                least = 2 if kind == "children2" else 1
                if not isinstance(v, list) or len(v) < least:
                    raise ModelError(f"{path}.children: must be a list of at least {least} "
                                     f"node{'s' if least > 1 else ''}, got {_describe(v)}")
                kids = [(c, f"{path}.children[{i}]") for i, c in enumerate(v)]
            elif kind == "child":
                kids = [(v, f"{path}.child")]
            else:
                fields[k] = _check_value(kind, v, f"{path}.{k}")
        order.append((t, fields, len(kids)))
        for c, cpath in reversed(kids):
            stack.append((c, cpath, depth + 1))
    # Pass 2 (reverse pre-order = children before parents): build immutable nodes.
    built = []
    for t, fields, nkids in reversed(order):
        kids = [built.pop() for _ in range(nkids)]
        cls = N.TYPES[t]
        if t in N.OPERATORS:
            node = cls(children=tuple(kids), **fields)
        elif t in N.UNARY:
            node = cls(child=kids[0], **fields)
        else:
            node = cls(**fields)
        built.append(node)
    assert len(built) == 1
    return built[0]


def loads(text):
    """Parse and validate a blobtree-1 JSON string."""
    if isinstance(text, (bytes, bytearray)):
        if len(text) > MAX_BYTES:
            raise ModelError(f"document: larger than {MAX_BYTES // 2**20} MiB")
        try:
            text = text.decode("utf-8")
        except UnicodeDecodeError as e:
            raise ModelError(f"document: not UTF-8 text ({e.reason} at byte {e.start})") from None
    if len(text) > MAX_BYTES:
        raise ModelError(f"document: larger than {MAX_BYTES // 2**20} MiB")
    try:
        doc = json.loads(text, parse_constant=_non_finite)
    except json.JSONDecodeError as e:
        raise ModelError(f"document: not valid JSON: {e.msg} at line {e.lineno} column {e.colno}") from None
    except RecursionError:
        raise ModelError(f"document: nesting too deep to be a model (limit {MAX_DEPTH} levels)") from None
    except ValueError as e:   # e.g. integers with too many digits
        raise ModelError(f"document: not a usable JSON number: {e}") from None
    return from_dict(doc)


def _non_finite(name):
    return _NonFinite(name)


def load(path):
    """Read a model file; errors name the file and the offending node."""
    try:
        with open(path, "rb") as fh:
            data = fh.read(MAX_BYTES + 1)
    except OSError as e:
        raise ModelError(f"{path}: cannot read: {e.strerror}") from None
    try:
        return loads(data)
    except ModelError as e:
        raise ModelError(f"{path}: {e}") from None


def _vec_out(v):
    return [_num_out(x) for x in v]


def _num_out(x):
    x = float(x)
    return int(x) if x.is_integer() and abs(x) < 2**53 else x


def to_dict(model):
    """The canonical JSON document of a model (default-valued optional keys omitted)."""
    built = []
    for node in reversed(list(N.iter_nodes(model.root))):   # children before parents
        if type(node) not in N.TYPE_NAME:
            raise TypeError(f"not a BlobTree node: {node!r:.60}")
        t = N.TYPE_NAME[type(node)]
        d = {"type": t}
        if node.name is not None:
            d["name"] = node.name
        for k, (kind, required) in SPEC[t].items():
            if kind in ("children", "children2"):
                d["children"] = [built.pop() for _ in node.children]
            elif kind == "child":
                d["child"] = built.pop()
            else:
                v = getattr(node, k)
                if not required and _is_default(k, v):
                    continue
                d[k] = _vec_out(v) if isinstance(v, tuple) else _num_out(v)
        built.append(d)
    doc = {"format": FORMAT, "name": model.name}
    if model.iso != 0.5:
        doc["iso"] = _num_out(model.iso)
    doc["root"] = built.pop()
    return doc


def _is_default(k, v):
    if k not in _DEFAULTS:
        return False
    dv = _DEFAULTS[k]
    return tuple(float(x) for x in v) == dv if isinstance(dv, tuple) else float(v) == dv


def fingerprint(model):
    """A short key of what a model's surface depends on: the sha1 of its canonical
    document without names (the model's or its nodes'), so two models with one key
    draw alike, and an edit of any value gives another."""
    def bare(v):
        if isinstance(v, dict):
            return {k: bare(x) for k, x in v.items() if k != "name"}
        return [bare(x) for x in v] if isinstance(v, list) else v
    text = json.dumps(bare(to_dict(model)), sort_keys=True, separators=(",", ":"))
    return hashlib.sha1(text.encode("utf-8")).hexdigest()[:16]


def dumps(model, indent=1):
    return json.dumps(to_dict(model), indent=indent)


def save(model, path):
    """Write a model atomically (a partial file never replaces a good one)."""
    import os
    import tempfile
    text = dumps(model)
    d = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(prefix=".blobtree-", suffix=".json", dir=d)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            fh.write(text)
            fh.write("\n")
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
