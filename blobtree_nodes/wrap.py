"""Wrapping a message to the width it is drawn at, measured with Blender's own UI font
at the size the preferences give it, so that no line is cut off and no text is lost
(a word too long for a line is split across lines)."""
import blf

FONT = 0            # Blender's UI font
# width in UI units (pixels at scale 1) that is not text: where an error box is drawn
# inside a node (the node's margins, the box, the icon) and inside a sidebar panel
NODE_CHROME = 64
PANEL_CHROME = 80


def ui_scale(context):
    # 0 when Blender runs without a window (blender -b, the bpy module): nothing is drawn there
    return context.preferences.system.ui_scale or 1.0


def node_text_width(context, node_width):
    """Pixels of text a line of a node ``node_width`` wide holds, at the UI scale."""
    return (node_width - NODE_CHROME) * ui_scale(context)


def region_text_width(context, region_width):
    """Pixels of text a line of a sidebar region ``region_width`` pixels wide holds."""
    return region_width - PANEL_CHROME * ui_scale(context)


def lines(text, width, context):
    """``text`` in lines of at most ``width`` pixels; every character is kept."""
    blf.size(FONT, context.preferences.ui_styles[0].widget.points * ui_scale(context))

    def fits(s):
        return blf.dimensions(FONT, s)[0] <= width

    out, cur = [], ""
    for word in text.split():
        joined = f"{cur} {word}" if cur else word
        if fits(joined):
            cur = joined
            continue
        if cur:
            out.append(cur)
        cur = ""
        for ch in word:                       # a word wider than a line: split it
            if cur and not fits(cur + ch):
                out.append(cur)
                cur = ""
            cur += ch
    if cur:
        out.append(cur)
    return out or [""]
