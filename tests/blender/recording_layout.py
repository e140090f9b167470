"""A stand-in for bpy.types.UILayout that records what a draw function puts in it, so
the Blender tier can check what an artist would see without a window: every item with
the containers it sits in (e.g. ("box", "column", "row"))."""
from types import SimpleNamespace


class Layout:
    def __init__(self, items=None, path=()):
        self.items = [] if items is None else items      # shared by every sub-layout
        self.path = path
        self.alert = False
        self.enabled = True
        self.operator_context = "INVOKE_DEFAULT"

    def _sub(self, kind, **kw):
        sub = Layout(self.items, self.path + (kind,))
        self.items.append(dict(kind=kind, path=self.path, **kw))
        return sub

    def box(self):
        return self._sub("box")

    def column(self, align=False, **kw):
        return self._sub("column", align=align)

    def row(self, align=False, **kw):
        return self._sub("row", align=align)

    def split(self, **kw):
        return self._sub("split")

    def grid_flow(self, **kw):
        return self._sub("grid_flow")

    def prop(self, data, prop, text=None, placeholder="", **kw):
        self.items.append(dict(kind="prop", path=self.path, data=data, prop=prop, text=text,
                               placeholder=placeholder, alert=self.alert))

    def label(self, text="", icon="NONE", **kw):
        self.items.append(dict(kind="label", path=self.path, text=text, icon=icon, alert=self.alert))

    def operator(self, idname, text=None, icon="NONE", **kw):
        props = SimpleNamespace()
        self.items.append(dict(kind="operator", path=self.path, idname=idname, text=text, icon=icon,
                               props=props, enabled=self.enabled, **kw))
        return props

    def menu(self, menu, **kw):
        self.items.append(dict(kind="menu", path=self.path, menu=menu))

    def menu_contents(self, menu):
        self.items.append(dict(kind="menu_contents", path=self.path, menu=menu))

    def separator(self, **kw):
        self.items.append(dict(kind="separator", path=self.path))

    def of(self, kind):
        return [i for i in self.items if i["kind"] == kind]


    def prop_names(self):
        """(prop item, the name an artist reads for it) for each property drawn: its
        text, else its property's name; drawn without text, the heading label above it
        in the same column, with the placeholder an empty field shows."""
        out = []
        for k, item in enumerate(self.items):
            if item["kind"] != "prop":
                continue
            if item["text"] is None:
                name = item["data"].bl_rna.properties[item["prop"]].name
            elif item["text"]:
                name = item["text"]
            else:
                heading = next((i["text"].rstrip(":") for i in reversed(self.items[:k])
                                if i["kind"] == "label" and i["path"] == item["path"]), "")
                name = f"{heading}: {item['placeholder']}" if item["placeholder"] else heading
            out.append((item, name))
        return out
