"""The engine in Blender's UI, for docs/images/blender-ui.png. Run under a virtual X server:

    BLENDER_USER_SCRIPTS=DIR PYTHONPATH=build/release/python xvfb-run -s "-screen 0 1600x900x24" \
        blender SCENE.blend --python-use-system-env --addons symphong_blender --python scripts/blender-addon/screenshot.py -- OUT.png

Renders the scene with symphong (F12's operator), shows the result in an Image Editor beside the Properties
editor on its Render tab (the symphong panel), takes a screenshot of the window and quits.
"""
import sys

import bpy

OUT = sys.argv[sys.argv.index("--") + 1]


def layout():
    window = bpy.context.window_manager.windows[0]
    screen = window.screen
    areas = sorted(screen.areas, key=lambda a: a.width * a.height, reverse=True)
    big = areas[0]
    big.type = "IMAGE_EDITOR"
    big.spaces.active.image = bpy.data.images.get("Render Result")
    for area in screen.areas:
        if area.type == "PROPERTIES":
            area.spaces.active.context = "RENDER"
    return window, big


def shoot():
    window, big = layout()
    region = next(r for r in big.regions if r.type == "WINDOW")
    with bpy.context.temp_override(window=window, screen=window.screen, area=big, region=region):
        bpy.ops.image.view_all(fit_view=True)
    bpy.app.timers.register(save, first_interval=1.0)
    return None


def save():
    window = bpy.context.window_manager.windows[0]
    with bpy.context.temp_override(window=window):
        bpy.ops.screen.screenshot(filepath=OUT)
    print(f"screenshot: {OUT}")
    bpy.ops.wm.quit_blender()
    return None


def render():
    bpy.context.scene.render.engine = "SYMPHONG"
    bpy.ops.render.render()
    bpy.app.timers.register(shoot, first_interval=1.0)
    return None


bpy.app.timers.register(render, first_interval=2.0)
