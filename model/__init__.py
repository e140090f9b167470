"""The BlobTree model: nodes, the blobtree-1 format, evaluation and curvature (numpy only)."""
from .nodes import Model, count_nodes, iter_nodes  # noqa: F401
from .format import ModelError, fingerprint, load, loads, save, dumps, to_dict, from_dict  # noqa: F401
from .evaluate import Evaluator, Stats  # noqa: F401
from .curvature import curvature, hessian  # noqa: F401


def key_of(ev):
    """The key (:func:`fingerprint`) of an evaluator's model, made once per evaluator."""
    memo = ev.memo
    return memo.get("fingerprint") or memo.setdefault("fingerprint", fingerprint(ev.model))
