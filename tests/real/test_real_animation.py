"""Issue #29 in the real Blender binary: an artist bakes an animation in the UI, and
`blender -b FILE.blend -a` renders an animated example frame by frame."""
import json
import os
import shutil

import numpy as np
from conftest import REPO, artifact, blender, darkest, read_png, run_ui_script


def test_real_ui_an_artist_bakes_an_animation(user_dir, tmp_path):
    """Issue #29 in the real UI (tests/real/ui/bake.py): Bake Frames from menu search
    bakes the scene's range; Esc while frame 3 is under way keeps frames 1 and 2; the
    whole range baked (Adjust Last Operation showing that range), the Right arrow steps
    the timeline and the viewport shows each frame's own drawing; Ctrl+Z undoes a bake as one step (and Ctrl+Shift+Z redoes it);
    Clear Frames clears them; a frame a render drew comes back when a Clear Frames after
    it is undone; with the driving Empty deleted in the viewport the bake fails
    on its first frame, draws nothing and keeps what was drawn."""
    out, facts = run_ui_script("bake.py", user_dir, tmp_path)
    assert "error" not in facts, facts.get("error")
    assert facts["held_frames"] == [1, 2] and facts["held_state"] == "running"
    assert facts["stopped_state"] == "stopped" and facts["stopped_frames"] == [1, 2]
    # Ctrl+Z while a bake runs stops it (not the step before it: the model stays)
    assert facts["undo_key_state"] == "stopped" and facts["undo_key_frames"] == [1, 2, 4]
    assert facts["tree_after_undo_key"] is True and facts["frames_after_undoing_the_stopped_bake"] == [1, 2]
    assert facts["frame_after_stop"] == 1                                   # back where the artist was
    assert facts["full_state"] == "done" and facts["full_frames"] == [1, 2, 3, 4, 5, 6]
    assert facts["last_operator"] == "BLOBTREE_INK_OT_bake" and facts["last_range"] == [1, 6]
    assert facts["redone_state"] == "done" and facts["redone_frames"] == [1, 2, 3, 4, 5, 6]
    right = [facts["silhouette_right"][str(f)] for f in range(1, 7)]
    assert right == sorted(right) and right[-1] > right[0] + 1.5            # following the Empty
    assert facts["frames_seen"] == [1, 2, 3, 4, 5, 6]
    assert facts["frames_after_undo"] == [1, 2] and facts["frames_after_redo"] == [1, 2, 3, 4, 5, 6]
    assert facts["frames_after_clear"] == []
    # a frame a render drew is an undo step of its own: undoing a later Clear Frames brings it back
    assert facts["frames_rendered"] == [2] and facts["frames_cleared_after_render"] == []
    assert facts["frames_after_undoing_the_clear"] == [2]
    assert facts["deleted_state"] == "failed" and facts["deleted_frames"] == [2]     # drew nothing, lost nothing
    shots = {}
    for name in ("bake_held.png", "bake_stopped.png", "bake_frame_1.png", "bake_frame_6.png"):
        shutil.copy(os.path.join(out, name), artifact(name))
        shots[name] = read_png(artifact(name)).astype(float).mean(axis=2) / 255
    pts = json.load(open(os.path.join(out, "bake_points.json")))
    six = np.array(pts["frame6"], float)
    assert len(six) > 20
    at6, at1 = darkest(shots["bake_frame_6.png"], six), darkest(shots["bake_frame_1.png"], six)
    # frame 6's silhouette is ink on screen at frame 6; at frame 1 the ball (and its ink) is elsewhere
    assert np.median(at6) < 0.3 and np.median(at1) - np.median(at6) > 0.2, (np.median(at6), np.median(at1))


def test_a_background_animation_render_of_an_example_scene(user_dir, tmp_path):
    """Issue #29: examples/animation/rigid.py builds a .blend of the heart turning;
    `blender -b FILE.blend -a` renders each frame with that frame's illustration (the
    render handler draws it): ink on paper that moves from frame to frame, and the
    frames' drawings saved in nothing but the render (the file is not written)."""
    blend = str(tmp_path / "rigid.blend")
    env = {"BLENDER_USER_RESOURCES": user_dir}
    blender("-b", "--factory-startup", "--python", os.path.join(REPO, "examples", "animation", "rigid.py"),
            "--", blend, env=env, timeout=600)
    p = blender("-b", blend, "-E", "BLENDER_WORKBENCH", "-o", str(tmp_path / "frame_####"), "-F", "PNG",
                "-s", "1", "-e", "3", "-a", env=env, timeout=900)
    frames = [read_png(str(tmp_path / f"frame_{f:04d}.png")).astype(float).mean(axis=2) / 255 for f in (1, 2, 3)]
    for f, img in zip((1, 2, 3), frames):
        shutil.copy(str(tmp_path / f"frame_{f:04d}.png"), artifact(f"animation_rigid_{f}.png"))
        ink = img < 0.5
        assert np.median(img) > 0.97, f"frame {f}: not on white paper"
        assert 0.002 < ink.mean() < 0.2, f"frame {f}: {ink.mean():.4f} of the image is ink"
    moved = [np.mean(np.abs((a < 0.5).astype(float) - (b < 0.5))) for a, b in zip(frames, frames[1:])]
    assert all(m > 0.001 for m in moved), moved                        # each frame its own drawing
    assert "Traceback" not in p.stdout + p.stderr
