"""Plain stroke data: what the Grease Pencil writer turns into strokes (no bpy)."""
from dataclasses import dataclass, field

import numpy as np

LAYERS = ("Silhouette", "Crease", "Curvature", "Suggestive", "Ridges", "Hatching", "Chains", "Short Strokes",
          "Stipples", "Single Strokes")
LAYER_OF_KIND = {"silhouette": "Silhouette", "crease": "Crease", "curvature": "Curvature", "suggestive": "Suggestive",
                 "ridges": "Ridges"}
STROKE_LAYERS = ("Hatching", "Chains", "Short Strokes", "Stipples")      # the style's stroke layers


@dataclass
class Stroke:
    points: np.ndarray               # (k, 3)
    radius: np.ndarray               # (k,) in scene units
    opacity: np.ndarray              # (k,) 0..1
    cyclic: bool = False
    dots: bool = False               # a stipple: drawn with the DOTS material
    mark: int = None                 # the key of the mark it was drawn from (model.marks), if any


@dataclass
class StrokeSet:
    layers: dict = field(default_factory=lambda: {name: [] for name in LAYERS})

    def add(self, layer, stroke):
        if layer not in self.layers:
            raise KeyError(f"unknown layer {layer!r}; one of {', '.join(LAYERS)}")
        self.layers[layer].append(stroke)

    def count(self, layer=None):
        return sum(len(v) for k, v in self.layers.items() if layer in (None, k))

    @classmethod
    def from_outlines(cls, outlines, radius, opacity=1.0):
        s = cls()
        for o in outlines:
            k = len(o.points)
            s.add(LAYER_OF_KIND[o.kind], Stroke(np.asarray(o.points, float), np.full(k, float(radius)),
                                                np.full(k, float(opacity)), cyclic=bool(o.closed)))
        return s
