"""The decision sites of a plan: one branch-record column per union, intersection,
union group and union stack, two per difference (model.branches)."""
from .groups import Group
from .plan_nodes import Op, Warp
from .stack import Stack, StackedGroup, StackedOp


class Sites:
    """Column numbers of a plan's decision sites: ``col[id(node)] = (first, per)``,
    ``per`` the columns of one part (a stack's member count inside its shape, else 1)."""

    def __init__(self, plan):
        self.col = {}
        self.count = 0

        def add(node, per, parts=1):
            self.col[id(node)] = (self.count, per)
            self.count += per * parts

        todo = [(plan, 1)]
        while todo:
            node, per = todo.pop()
            if isinstance(node, (Group, StackedGroup)):
                if node.reduce == "max" and node.m > 1:
                    add(node, per)
            elif isinstance(node, Stack):
                if node.reduce == "max":
                    add(node, per)
                todo.append((node.shape, node.K))
            elif isinstance(node, Warp):
                todo.append((node.child, per))
            elif isinstance(node, (Op, StackedOp)):
                if node.op in ("union", "intersection"):
                    add(node, per)
                elif node.op == "difference":
                    add(node, per, parts=2)
                todo.extend((c, per) for c in node.children)
        self._plan = plan          # the ids above are of this plan's nodes: keep it alive
