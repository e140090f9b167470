"""Generate the bundled example models (blobtree-1 JSON) deterministically.

    python examples/make_examples.py        # rewrites examples/*.json

Analogues of the papers' models (pear with a bite and a stalk, jug with a handle,
heart with veins ~76 nodes, train ~723 nodes, spiral shell 1497 nodes) and tiny
analytic models for tests.
"""
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools"))
import pure  # noqa: E402

pure.install()
import numpy as np  # noqa: E402
from blobtree_ink.model import nodes as N  # noqa: E402
from blobtree_ink.model import format as F  # noqa: E402
from blobtree_ink.model.evaluate import Evaluator  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
K = math.sqrt(1 - 0.5 ** (1 / 3))    # iso radius of a lone point = K * R


def v(*a):
    return tuple(float(x) for x in a)


def P(c, R, s=1.0, name=None):
    return N.Point(center=v(*c), radius=float(R), strength=float(s), name=name)


def S(a, b, R, s=1.0, name=None):
    return N.Segment(a=v(*a), b=v(*b), radius=float(R), strength=float(s), name=name)


def T(child, translate=(0, 0, 0), rotate=(0, 0, 0), scale=(1, 1, 1), name=None):
    return N.Transform(child=child, translate=v(*translate), rotate=v(*rotate), scale=v(*scale), name=name)


# --- tiny analytic models --------------------------------------------------------------

def sphere():
    return N.Model(name="sphere", root=P((0, 0, 0), 1.0))


def two_spheres():
    return N.Model(name="two_spheres", root=N.Blend(children=(P((-0.4, 0, 0), 1.0), P((0.4, 0, 0), 1.0))))


def torus():
    return N.Model(name="torus", root=N.Circle(center=v(0, 0, 0), normal=v(0, 0, 1), circle_radius=1.0,
                                              radius=0.8))


def csg_difference():
    # a ball of iso radius K*1.5 minus a ball of iso radius K*1.0 centred 0.6 away
    return N.Model(name="csg_difference", root=N.Difference(children=(P((0, 0, 0), 1.5), P((0.6, 0, 0), 1.0))))


def csg_union():
    return N.Model(name="csg_union", root=N.Union(children=(P((-0.3, 0, 0), 1.5), P((0.3, 0, 0), 1.5))))


# --- the papers' models ----------------------------------------------------------------

def pear():
    body = N.Blend(name="body", children=(
        P((0, 0, 0), 1.9, name="belly"),
        P((0, 0, 0.95), 1.25, name="neck"),
        S((0, 0, 1.35), (0.12, 0.04, 1.95), 0.13, name="stalk"),
    ))
    bite = P((1.05, -0.45, 0.2), 1.15, name="bite")
    return N.Model(name="pear", root=N.Difference(name="pear", children=(body, bite)))


def jug():
    belly = N.Taper(name="taper", rate=-0.22,
                    child=S((0, 0, -0.7), (0, 0, 0.5), 1.9, name="belly"))
    rim = N.Circle(name="rim", center=v(0, 0, 1.05), normal=v(0, 0, 1), circle_radius=0.42, radius=0.42)
    spout = S((0.35, 0, 1.05), (0.75, 0, 1.25), 0.3, name="spout")
    hollow = P((0, 0, 1.35), 0.85, name="mouth")
    body = N.Difference(name="body", children=(N.Blend(children=(belly, rim, spout)), hollow))
    ring = T(N.Circle(center=v(0, 0, 0), normal=v(0, 0, 1), circle_radius=0.55, radius=0.32),
             translate=(-0.75, 0, 0.35), rotate=(math.pi / 2, 0, 0), scale=(1.0, 1.25, 1.0), name="handle ring")
    keep = N.Box(name="outer half", center=v(-1.5, 0, 0.35), half_size=v(0.8, 0.6, 1.2), radius=0.05)
    handle = N.Intersection(name="handle", children=(ring, keep))
    return N.Model(name="jug", root=N.Union(name="jug", children=(body, handle)))


def _cast_front(ev, xz, iso=0.5, y0=-3.0, y1=1.0, steps=400):
    """Points where rays from y0 towards +y first enter the solid (f >= iso)."""
    out = []
    ys = np.linspace(y0, y1, steps)
    for x, z in xz:
        P = np.stack([np.full(steps, x), ys, np.full(steps, z)], axis=1)
        f = ev.field(P)
        i = int(np.argmax(f >= iso))
        if f[i] < iso:
            continue
        a, b = ys[i - 1], ys[i]
        for _ in range(40):
            m = 0.5 * (a + b)
            if ev.field([[x, m, z]])[0] >= iso:
                b = m
            else:
                a = m
        out.append((x, b, z))
    return np.array(out)


def heart():
    body_parts = (P((-0.45, 0, 0.45), 1.7, name="left lobe"), P((0.45, 0, 0.45), 1.7, name="right lobe"),
                  S((0, 0, 0.2), (0.05, 0, -0.95), 1.05, name="apex"))
    vessels = (S((-0.2, 0, 1.0), (-0.35, 0.1, 1.6), 0.55, name="aorta"),
               S((0.25, 0.05, 0.95), (0.45, 0.0, 1.45), 0.45, name="pulmonary"),
               S((-0.35, 0.1, 1.6), (-0.7, 0.1, 1.7), 0.4, name="arch"),
               S((0.45, 0.0, 1.45), (0.75, -0.05, 1.5), 0.35, name="branch"))
    base = N.Model(root=N.Blend(children=body_parts))
    ev = Evaluator(base)
    veins = []
    rng = np.random.default_rng(7)
    for k in range(7):
        a0 = -0.9 + 0.3 * k
        t = np.linspace(0, 1, 10 if k < 6 else 8)
        xz = np.stack([a0 * (1 - 0.6 * t) + 0.15 * np.sin(5 * t + k) + rng.normal(0, 0.03, len(t)),
                       0.9 - 1.5 * t], axis=1)
        on = _cast_front(ev, xz)
        segs = tuple(S(on[i], on[i + 1], 0.11, s=0.4) for i in range(len(on) - 1))
        veins.append(N.Blend(name=f"vein {k + 1}", children=segs))
    root = N.Blend(name="heart", children=(*body_parts, *vessels, *veins))
    return N.Model(name="heart", root=root)


def _wheel(x, y, z, r, spokes=6):
    rim = N.Disc(center=v(0, 0, 0), normal=v(0, 1, 0), disc_radius=r, radius=0.12, name="wheel")
    holes = tuple(P((0.55 * r * math.cos(2 * math.pi * i / spokes), 0, 0.55 * r * math.sin(2 * math.pi * i / spokes)),
                    0.42 * r) for i in range(spokes))
    hub = P((0, 0, 0), 0.35 * r, name="hub")
    w = N.Union(children=(N.Difference(children=(rim, *holes)), hub))
    return T(w, translate=(x, y, z), name="wheel placement")


def _car(x0, length, height, windows, rivets_per_side):
    shell = N.Box(center=v(x0, 0, 0.9), half_size=v(length / 2, 0.55, height / 2), radius=0.15, name="car body")
    wins = tuple(N.Box(center=v(x0 - length / 2 + (i + 0.75) * length / (windows + 0.5), -0.7, 1.1),
                       half_size=v(0.12, 0.2, 0.12), radius=0.08) for i in range(windows))
    body = N.Difference(name="car with windows", children=(shell, *wins))
    rivets = tuple(P((x0 - length / 2 + (i + 0.5) * length / rivets_per_side, side * 0.72, 0.45), 0.09)
                   for side in (-1, 1) for i in range(rivets_per_side))
    wheels = tuple(_wheel(x0 + dx, side * 0.62, 0.3, 0.3)
                   for dx in (-length / 3, length / 3) for side in (-1, 1))
    return N.Union(name="car", children=(N.Blend(children=(body, *rivets)), *wheels))


def train():
    boiler = S((-1.2, 0, 1.0), (1.2, 0, 1.0), 1.25, name="boiler")
    stack = N.Taper(rate=0.6, child=S((0, 0, 0), (0, 0, 0.6), 0.45, name="smokestack"), name="stack taper")
    stack = T(stack, translate=(0.8, 0, 1.35))
    dome = P((0.0, 0, 1.45), 0.7, name="dome")
    cab_shell = N.Box(center=v(-1.65, 0, 1.25), half_size=v(0.5, 0.55, 0.6), radius=0.12, name="cab")
    cab_windows = tuple(N.Box(center=v(-1.65 + dx, side * 0.7, 1.45), half_size=v(0.15, 0.2, 0.18), radius=0.06)
                        for dx in (-0.22, 0.22) for side in (-1, 1))
    cab = N.Difference(name="cab with windows", children=(cab_shell, *cab_windows))
    rivets = tuple(P((-1.1 + 0.08 * i, side * 0.5 * math.cos(a), 1.0 + 0.5 * math.sin(a)), 0.08)
                   for i in range(29) for side in (-1, 1) for a in (0.4, -0.4))
    loco_body = N.Blend(name="locomotive body", children=(boiler, stack, dome, *rivets))
    wheels = tuple(_wheel(x, side * 0.62, 0.35, 0.35) for x in (-1.0, -0.2, 0.6) for side in (-1, 1))
    frame = N.Box(center=v(-0.3, 0, 0.45), half_size=v(1.6, 0.45, 0.08), radius=0.1, name="frame")
    loco = N.Union(name="locomotive", children=(loco_body, cab, frame, *wheels))
    cars = tuple(_car(-4.0 - 3.2 * i, 2.6, 1.0, 5, 26) for i in range(5))
    return N.Model(name="train", root=N.Union(name="train", children=(loco, *cars)))


def shell():
    """A turreted spiral shell: a whorl tube of blended segments along a logarithmic
    helix, three spiral rows of nodules on it, and the aperture cut away (1497 nodes)."""
    turns, n_seg, rows, per_row = 5.3, 72, 3, 237
    th_max = turns * 2 * math.pi

    def centre(th):
        grow = math.exp(0.085 * th)
        return np.array([0.12 * grow * math.cos(th), 0.12 * grow * math.sin(th), 2.0 - 0.35 * (grow - 1)]), grow

    pts = [centre(th_max * k / n_seg) for k in range(n_seg + 1)]
    tube = tuple(S(pts[k][0], pts[k + 1][0], 0.17 * pts[k][1], name=f"whorl {k + 1}") for k in range(n_seg))
    nodules = []
    for row, (lift, out) in enumerate(((0.55, 0.75), (0.0, 1.0), (-0.5, 0.8))):
        for k in range(per_row):
            th = th_max * (k + 0.5 * row) / per_row
            c, grow = centre(th)
            radial = np.array([math.cos(th), math.sin(th), 0.0])
            pos = c + 0.12 * grow * (out * radial + np.array([0, 0, lift]))
            size = 0.055 * grow
            nodules.append(T(P((0, 0, 0), 1.0), translate=pos, rotate=(0.0, 0.0, th),
                             scale=(size, size, size)))
    end, grow = centre(th_max)
    mouth = P(end + 0.02 * grow * np.array([math.cos(th_max), math.sin(th_max), 0.0]), 0.2 * grow,
              name="aperture")
    body = N.Blend(name="whorls", children=tube + tuple(nodules))
    return N.Model(name="shell", root=N.Difference(name="shell", children=(body, mouth)))


MODELS = (sphere, two_spheres, torus, csg_difference, csg_union, pear, jug, heart, train, shell)


def main():
    for make in MODELS:
        m = make()
        path = os.path.join(HERE, f"{m.name}.json")
        F.save(m, path)
        print(f"{m.name}: {N.count_nodes(m)} nodes -> {os.path.relpath(path)}")


if __name__ == "__main__":
    main()
