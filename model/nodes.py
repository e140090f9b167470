"""Plain node objects of a BlobTree model (the blobtree-1 format, one class per type).

These are immutable descriptions; evaluation lives in :mod:`.evaluate`.
"""
from dataclasses import dataclass, field
from typing import Optional, Tuple

Vec3 = Tuple[float, float, float]


@dataclass(frozen=True)
class Node:
    name: Optional[str] = field(default=None, kw_only=True)


@dataclass(frozen=True)
class Point(Node):
    center: Vec3
    radius: float
    strength: float = 1.0


@dataclass(frozen=True)
class Segment(Node):
    a: Vec3
    b: Vec3
    radius: float
    strength: float = 1.0


@dataclass(frozen=True)
class Circle(Node):
    center: Vec3
    normal: Vec3
    circle_radius: float
    radius: float
    strength: float = 1.0


@dataclass(frozen=True)
class Disc(Node):
    center: Vec3
    normal: Vec3
    disc_radius: float
    radius: float
    strength: float = 1.0


@dataclass(frozen=True)
class Box(Node):
    center: Vec3
    half_size: Vec3
    radius: float
    strength: float = 1.0


@dataclass(frozen=True)
class Blend(Node):
    children: Tuple[Node, ...]


@dataclass(frozen=True)
class Ricci(Node):
    children: Tuple[Node, ...]
    n: float


@dataclass(frozen=True)
class Union(Node):
    children: Tuple[Node, ...]


@dataclass(frozen=True)
class Intersection(Node):
    children: Tuple[Node, ...]


@dataclass(frozen=True)
class Difference(Node):
    children: Tuple[Node, ...]


@dataclass(frozen=True)
class Transform(Node):
    child: Node
    translate: Vec3 = (0.0, 0.0, 0.0)
    rotate: Vec3 = (0.0, 0.0, 0.0)
    scale: Vec3 = (1.0, 1.0, 1.0)


@dataclass(frozen=True)
class Twist(Node):
    child: Node
    rate: float


@dataclass(frozen=True)
class Taper(Node):
    child: Node
    rate: float


@dataclass(frozen=True)
class Bend(Node):
    child: Node
    rate: float


PRIMITIVES = {"point": Point, "segment": Segment, "circle": Circle, "disc": Disc, "box": Box}
OPERATORS = {"blend": Blend, "ricci": Ricci, "union": Union,
             "intersection": Intersection, "difference": Difference}
UNARY = {"transform": Transform, "twist": Twist, "taper": Taper, "bend": Bend}
TYPES = {**PRIMITIVES, **OPERATORS, **UNARY}
TYPE_NAME = {cls: name for name, cls in TYPES.items()}


@dataclass(frozen=True)
class Model:
    root: Node
    name: str = "model"
    iso: float = 0.5


def iter_nodes(node):
    """Every node of the tree, depth first, parents before children (iterative)."""
    stack = [node]
    while stack:
        n = stack.pop()
        yield n
        if isinstance(n, (Blend, Ricci, Union, Intersection, Difference)):
            stack.extend(reversed(n.children))
        elif isinstance(n, (Transform, Twist, Taper, Bend)):
            stack.append(n.child)


def count_nodes(model_or_node):
    node = model_or_node.root if isinstance(model_or_node, Model) else model_or_node
    return sum(1 for _ in iter_nodes(node))
