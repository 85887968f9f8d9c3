"""symphong as a Blender render engine (docs/blender.md).

F12 renders the evaluated scene with symphong's Python module: meshes, materials, lights, world and camera
handed over as arrays (convert.py, symphong.Scene.from_arrays), rendered pass by pass (symphong.Progressive)
into Blender's render result, with its progress bar and Esc. The render settings panel is built from the
module's settings schema (symphong.render_settings()): the command line's names, defaults and ranges.

Where the module comes from, in this order: the add-on preference "Module folder" (e.g. the build's
build/release/python), an installed module (`cmake --install build/release --component python`), the folders
of PYTHONPATH (Blender reads it when started with --python-use-system-env), and last the build beside this
add-on's own checkout (<repository>/build/release/python, when the add-on is the repository's folder or a link
to it).
"""

bl_info = {
    "name": "symphong",
    "author": "symphong",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "Render Properties > Render Engine > symphong",
    "description": "Render with symphong, a Phong path tracer (estimators, samplers, symmetric sampling)",
    "category": "Render",
}

import importlib
import os
import sys
import threading
import time

import bpy

from . import convert

# The schema keys the add-on sets itself (the picture's size from Blender's output settings) or that a render
# in passes does not take (its own stop rules and checkpoints: Blender's render is the pass loop).
OWN_KEYS = {"width", "height", "time", "target_error", "target_region", "pass_spp", "checkpoint", "checkpoint_interval", "resume"}

_module = None
_module_error = ""
_module_origin = ""


def _addon_prefs():
    addon = bpy.context.preferences.addons.get(__package__)
    return addon.preferences if addon else None


def _try_import(path=None):
    """The symphong module, imported from `path` (first on sys.path) or from sys.path as it is."""
    global _module
    if path:
        path = os.path.abspath(os.path.expanduser(path))
        if not os.path.isdir(path):
            raise ImportError(f"{path} is not a folder")
        if path in sys.path:
            sys.path.remove(path)
        sys.path.insert(0, path)
    if "symphong" in sys.modules:
        mod = sys.modules["symphong"]
        if path and os.path.dirname(os.path.abspath(mod.__file__)) != path:
            raise ImportError(f"another symphong module is already loaded ({mod.__file__}); restart Blender to switch")
        return mod
    return importlib.import_module("symphong")


def load_module():
    """symphong, found as the module docstring says; raises ImportError naming every place tried."""
    global _module, _module_error, _module_origin
    if _module is not None:
        return _module
    tried = []
    prefs = _addon_prefs()
    candidates = []
    if prefs is not None and prefs.module_path:
        candidates.append(("preference", prefs.module_path))
    candidates.append(("installed", None))
    for entry in os.environ.get("PYTHONPATH", "").split(os.pathsep):
        if entry:
            candidates.append(("PYTHONPATH", entry))
    here = os.path.dirname(os.path.realpath(__file__))
    candidates.append(("checkout", os.path.join(here, "..", "..", "build", "release", "python")))
    for origin, path in candidates:
        try:
            _module = _try_import(path)
            _module_origin = f"{origin}: {os.path.dirname(_module.__file__)}"
            _module_error = ""
            return _module
        except ImportError as e:
            tried.append(f"{origin} ({path or 'sys.path'}): {e}")
    _module_error = "symphong module not found. Tried " + "; ".join(tried)
    raise ImportError(_module_error)


# ---------------------------------------------------------------------------------------------- settings


def _settings_annotations(sym):
    """Blender properties for the render settings of the module's schema (name, default, range, choices)."""
    ann = {}
    for f in sym.render_settings():
        name = f["name"]
        if name in OWN_KEYS or f["type"] == "list":
            continue
        label = name.replace("_", " ").capitalize()
        desc = f"{f['flag']}: {f['help']}"
        if f["choices"]:
            items = [(str(c), str(c), "") for c in f["choices"]]
            ann[name] = bpy.props.EnumProperty(name=label, description=desc, items=items, default=str(f["default"]))
        elif f["type"] == "bool":
            ann[name] = bpy.props.BoolProperty(name=label, description=desc, default=bool(f["default"]))
        elif f["type"] == "int":
            lo = int(max(f["min"], -(2**31))) if f["min"] is not None else 0
            hi = int(min(f["max"], 2**31 - 1)) if f["max"] is not None else 2**31 - 1
            ann[name] = bpy.props.IntProperty(name=label, description=desc, default=int(f["default"]), min=lo, max=hi)
        elif f["type"] == "float":
            kw = {}
            if f["min"] is not None:
                kw["min"] = f["min"]
            if f["max"] is not None:
                kw["max"] = f["max"]
            ann[name] = bpy.props.FloatProperty(name=label, description=desc, default=float(f["default"]), **kw)
        else:
            ann[name] = bpy.props.StringProperty(name=label, description=desc, default=str(f["default"]))
    return ann


_settings_class = None
_schema = []


def _register_settings():
    global _settings_class, _schema
    ann = {}
    try:
        sym = load_module()
        ann = _settings_annotations(sym)
        _schema = [f for f in sym.render_settings() if f["name"] in ann]
    except ImportError:
        _schema = []
    cls = type("SymphongRenderSettings", (bpy.types.PropertyGroup,), {"__annotations__": ann})
    bpy.utils.register_class(cls)
    bpy.types.Scene.symphong = bpy.props.PointerProperty(type=cls)
    _settings_class = cls


def _unregister_settings():
    global _settings_class
    if _settings_class is not None:
        del bpy.types.Scene.symphong
        bpy.utils.unregister_class(_settings_class)
        _settings_class = None


def render_keywords(scene):
    """The render() keywords of the scene's settings panel."""
    kw = {}
    settings = scene.symphong
    for f in _schema:
        value = getattr(settings, f["name"])
        if f["choices"] and isinstance(f["choices"][0], int):
            value = int(value)
        kw[f["name"]] = value
    return kw


def _module_path_changed(self, context):
    global _module
    if "symphong" not in sys.modules:
        _module = None
    _unregister_settings()
    _register_settings()


class SymphongPreferences(bpy.types.AddonPreferences):
    bl_idname = __package__

    module_path: bpy.props.StringProperty(
        name="Module folder",
        description="Folder holding the symphong Python module (e.g. <repository>/build/release/python); empty: installed module or PYTHONPATH",
        subtype="DIR_PATH",
        update=_module_path_changed,
    )

    def draw(self, context):
        self.layout.prop(self, "module_path")
        if _module is not None:
            self.layout.label(text=f"symphong {_module.__version__} ({_module_origin})")
        elif _module_error:
            self.layout.label(text=_module_error[:200], icon="ERROR")


# ---------------------------------------------------------------------------------------------- engine


class SymphongRenderEngine(bpy.types.RenderEngine):
    bl_idname = "SYMPHONG"
    bl_label = "symphong"
    bl_use_preview = False
    bl_use_postprocess = True
    bl_use_eevee_viewport = True  # the viewport's Material Preview / Rendered shading through EEVEE

    def render(self, depsgraph):
        scene = depsgraph.scene
        r = scene.render
        width = int(r.resolution_x * r.resolution_percentage / 100)
        height = int(r.resolution_y * r.resolution_percentage / 100)
        try:
            sym = load_module()
        except ImportError as e:
            self.report({"ERROR"}, str(e))
            return
        self.update_stats("", "symphong: converting the scene")
        t0 = time.perf_counter()
        try:
            kwargs, reports = convert.convert(depsgraph, width, height)
            sym_scene = sym.Scene.from_arrays(**kwargs)
        except (ValueError, TypeError, FileNotFoundError) as e:
            self.report({"ERROR"}, f"symphong: {e}")
            return
        seconds = time.perf_counter() - t0
        for level, message in reports:
            self.report({level}, f"symphong: {message}")
        for w in sym_scene.warnings:
            self.report({"WARNING"}, f"symphong: {w}")
        print(f"symphong: scene converted in {seconds:.3f} s ({sym_scene.triangle_count} triangles)")
        try:
            render = sym.Progressive(sym_scene, width=width, height=height, **render_keywords(scene))
        except (ValueError, TypeError) as e:
            self.report({"ERROR"}, f"symphong: {e}")
            return
        self._render_passes(render, width, height)

    def _render_passes(self, render, width, height):
        import numpy as np

        result = self.begin_result(0, 0, width, height)
        layer = result.layers[0].passes["Combined"]
        stop = threading.Event()
        finished = threading.Event()

        def watch():  # Esc during a pass: cancel it after the tiles in flight
            while not finished.wait(0.1):
                if self.test_break():
                    stop.set()
                    render.cancel()
                    return

        watcher = threading.Thread(target=watch, daemon=True)
        watcher.start()
        spp, step, reached = render.spp, 1, 0
        rgba = np.ones((height, width, 4), dtype=np.float32)
        try:
            while reached < spp and not stop.is_set():
                t = time.perf_counter()
                image = render.advance(min(spp, reached + step))
                reached = render.samples_reached
                rendered = time.perf_counter() - t
                rgba[:, :, :3] = image[::-1]  # Blender's rows start at the bottom
                layer.rect.foreach_set(rgba.reshape(-1, 4))
                self.update_result(result)
                self.update_progress(reached / spp)
                self.update_stats("", f"symphong: {reached}/{spp} samples per pixel")
                # Passes of about a second (Esc and the picture stay responsive), and long enough that showing
                # the picture costs at most a tenth of the time.
                shown = time.perf_counter() - t - rendered
                if rendered < max(0.5, 10 * shown):
                    step = min(step * 2, 1 << 16)
                if self.test_break():
                    break
        finally:
            finished.set()
            watcher.join()
            self.end_result(result)
        stats = render.stats()
        print(f"symphong: {stats['spp_reached']} spp in {stats['seconds']:.2f} s ({stats['estimator']}, {stats['sampler']})")


# ---------------------------------------------------------------------------------------------- panels


class SYMPHONG_PT_render(bpy.types.Panel):
    bl_label = "symphong"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "render"

    @classmethod
    def poll(cls, context):
        return context.engine == "SYMPHONG"

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        if not _schema:
            layout.label(text="symphong module not found: set its folder in the add-on's preferences", icon="ERROR")
            return
        for f in _schema:
            layout.prop(context.scene.symphong, f["name"])


def _compatible_panels():
    """Blender's own panels to show under this engine: those EEVEE shows for materials, world, lights and output."""
    names = []
    for panel in bpy.types.Panel.__subclasses__():
        engines = getattr(panel, "COMPAT_ENGINES", None)
        if not engines:
            continue
        context = getattr(panel, "bl_context", "")
        if "BLENDER_RENDER" in engines or ("BLENDER_EEVEE" in engines and context in {"material", "world", "data", "output"}):
            names.append(panel)
    return names


classes = (SymphongPreferences, SymphongRenderEngine, SYMPHONG_PT_render)


def register():
    for cls in classes:
        bpy.utils.register_class(cls)
    _register_settings()
    for panel in _compatible_panels():
        panel.COMPAT_ENGINES.add("SYMPHONG")


def unregister():
    for panel in _compatible_panels():
        panel.COMPAT_ENGINES.discard("SYMPHONG")
    _unregister_settings()
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
