#!/usr/bin/env python3
"""Writes tests/data/fbx/box.fbx, the FBX file that tests/test_assimp.cpp loads through Assimp.

Usage: python3 scripts/make-test-fbx.py [OUTPUT]   (default: tests/data/fbx/box.fbx beside this script)

Why: symphong reads FBX through Assimp 5.2, which cannot read back the FBX its own exporter writes
("FBX-Tokenize ... block offset is out of range"), so the test needs an FBX file made another way. This
script writes one by hand, standard library only, as an ASCII FBX 7.4 file laid out like those of the
FBX SDK (FBXHeaderExtension, GlobalSettings, Documents, Definitions with property templates, Objects,
Connections), with every value the test checks written explicitly on its object:

- units and axes: UpAxis 1 (+Y up), FrontAxis 2 (+Z), CoordAxis 0 (+X): right-handed, y up, as symphong
  and glTF. UnitScaleFactor 100 (one unit = 100 cm = 1 m): the coordinates below are metres. Assimp 5.2
  leaves the coordinates as written (it only records the factor in the scene's metadata and would
  scale by UnitScaleFactor / 100 = 1 under aiProcess_GlobalScale, which symphong does not request).
- "Box": a closed box from (0, 0, 0) to (2, 1, 3), Model "Box" with the identity transform; 8 vertices,
  6 outward-facing quads (counter-clockwise seen from outside; the last index of each polygon is
  written as its ones' complement, -(i + 1)), one normal per polygon vertex (LayerElementNormal
  ByPolygonVertex, Direct) and one material per polygon (LayerElementMaterial ByPolygon,
  IndexToDirect): the bottom, back, front, left and right faces use material 0, the top (y = 1) face
  material 1. Surface area 2 (2*3 + 2*1 + 1*3) = 22; 12 triangles once triangulated.
- materials (Phong; indices in the order of their connections to the Model):
  0 "white": DiffuseColor 0.7, SpecularColor 0.2, ShininessExponent 20, EmissiveColor 0;
  1 "lamp": DiffuseColor 0, SpecularColor 0, ShininessExponent 1, EmissiveColor (5, 5, 5).
  Every *Factor is 1, so that colour x factor (the FBX SDK's meaning) is the colour itself.
- Model "Camera" with NodeAttribute Camera: Lcl Translation (1, 0.5, 10), Lcl Rotation (0, 90, 0)
  degrees. An FBX camera looks along its node's +X with +Y up; turned 90 degrees about +Y it looks
  along -Z, at the box's centre (1, 0.5, 1.5). FieldOfView 60 degrees, the full horizontal angle
  (ApertureMode 1 = horizontal; FieldOfViewX 60 and FieldOfViewY = 2 atan(tan(30 deg) / aspect) are
  written too, as Blender does), AspectWidth 640 x AspectHeight 480 (aspect 4/3).
- Model "PointLight" with NodeAttribute Light: LightType 0 (point), Lcl Translation (1, 2.5, 1.5),
  Color (1, 0.9, 0.8), Intensity 250 (FBX intensities are percentages: Assimp gives the colour times
  2.5), DecayType 2 (quadratic, i.e. inverse square).

The output is deterministic (fixed time stamps), so rerunning the script leaves the committed file as
it is.
"""
import math
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEFAULT_OUT = os.path.join(ROOT, "tests", "data", "fbx", "box.fbx")

# --- The scene -----------------------------------------------------------------------------------

BOX_LO, BOX_HI = (0.0, 0.0, 0.0), (2.0, 1.0, 3.0)
# Corner i has x from bit 0, y from bit 1, z from bit 2.
VERTICES = [tuple((BOX_HI if (i >> k) & 1 else BOX_LO)[k] for k in range(3)) for i in range(8)]
# Quads, counter-clockwise seen from outside, with their outward normals and material indices.
FACES = [
    ((0, 1, 5, 4), (0, -1, 0), 0),  # bottom, y = 0
    ((0, 2, 3, 1), (0, 0, -1), 0),  # back, z = 0
    ((4, 5, 7, 6), (0, 0, 1), 0),   # front, z = 3
    ((0, 4, 6, 2), (-1, 0, 0), 0),  # left, x = 0
    ((1, 3, 7, 5), (1, 0, 0), 0),   # right, x = 2
    ((2, 6, 7, 3), (0, 1, 0), 1),   # top, y = 1: the lamp
]
MATERIALS = [
    {"name": "white", "diffuse": (0.7, 0.7, 0.7), "specular": (0.2, 0.2, 0.2), "shininess": 20.0, "emissive": (0.0, 0.0, 0.0)},
    {"name": "lamp", "diffuse": (0.0, 0.0, 0.0), "specular": (0.0, 0.0, 0.0), "shininess": 1.0, "emissive": (5.0, 5.0, 5.0)},
]
CAMERA = {"translation": (1.0, 0.5, 10.0), "rotation": (0.0, 90.0, 0.0), "fov": 60.0, "width": 640, "height": 480,
          "near": 0.1, "far": 100.0}
LIGHT = {"translation": (1.0, 2.5, 1.5), "color": (1.0, 0.9, 0.8), "intensity": 250.0}
UNIT_SCALE_FACTOR = 100.0  # centimetres per unit: metres

# Object ids (FBX ids are 64-bit integers; 0 is the scene's root node).
ID_DOCUMENT = 1000000
ID_BOX_MODEL, ID_BOX_GEOMETRY = 1000001, 1000002
ID_MATERIALS = [1000003, 1000004]
ID_CAMERA_MODEL, ID_CAMERA_ATTR = 1000005, 1000006
ID_LIGHT_MODEL, ID_LIGHT_ATTR = 1000007, 1000008


def check_geometry():
    """Asserts that every face is planar, wound outwards and matches its stated normal."""
    for quad, normal, _ in FACES:
        p = [VERTICES[i] for i in quad]
        e1 = [p[1][k] - p[0][k] for k in range(3)]
        e2 = [p[2][k] - p[0][k] for k in range(3)]
        c = (e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0])
        length = math.sqrt(sum(x * x for x in c))
        assert all(abs(c[k] / length - normal[k]) < 1e-12 for k in range(3)), (quad, c, normal)
        assert all(sum((p[j][k] - p[0][k]) * normal[k] for k in range(3)) == 0 for j in range(4)), quad


# --- Writing -------------------------------------------------------------------------------------


def num(x):
    """A number as FBX SDK ASCII files write it: integers without a decimal point, else up to 15 digits."""
    x = float(x)
    if x == int(x) and abs(x) < 1e15:
        return str(int(x))
    return f"{x:.15g}"


def nums(values):
    return ",".join(num(v) for v in values)


def prop(name, type_, label, flags, *values):
    """One Properties70 line: P: "name", "type", "label", "flags", values."""
    vals = ",".join(f'"{v}"' if isinstance(v, str) else num(v) for v in values)
    return f'P: "{name}", "{type_}", "{label}", "{flags}",{vals}'


def color(name, rgb, animatable=True):
    return prop(name, "Color", "", "A" if animatable else "", *rgb)


def number(name, value, animatable=True):
    return prop(name, "Number", "", "A" if animatable else "", value)


def array(name, values, per_line=12):
    """A typed array, ASCII 7.x style: Name: *count { a: v,v,... }."""
    chunks = [nums(values[i:i + per_line]) for i in range(0, len(values), per_line)]
    body = ["\t" + ("a: " if i == 0 else "   ") + c + ("," if i + 1 < len(chunks) else "") for i, c in enumerate(chunks)]
    return [f"{name}: *{len(values)} {{"] + body + ["}"]


class Writer:
    def __init__(self):
        self.lines = []
        self.depth = 0

    def line(self, text=""):
        self.lines.append("\t" * self.depth + text if text else "")

    def block(self, header):
        self.line(header + " {")
        self.depth += 1

    def end(self):
        self.depth -= 1
        self.line("}")

    def props(self, entries):
        self.block("Properties70: ")
        for e in entries:
            self.line(e)
        self.end()

    def raw(self, lines):
        for text in lines:
            self.line(text)

    def text(self):
        return "\n".join(self.lines) + "\n"


def model_props(translation=(0, 0, 0), rotation=(0, 0, 0)):
    return [
        prop("RotationActive", "bool", "", "", 1),
        prop("InheritType", "enum", "", "", 1),
        prop("ScalingMax", "Vector3D", "Vector", "", 0, 0, 0),
        prop("DefaultAttributeIndex", "int", "Integer", "", 0),
        prop("Lcl Translation", "Lcl Translation", "", "A", *translation),
        prop("Lcl Rotation", "Lcl Rotation", "", "A", *rotation),
        prop("Lcl Scaling", "Lcl Scaling", "", "A", 1, 1, 1),
    ]


def camera_vectors():
    """The camera's world position, target (one unit ahead) and up: its node's +X and +Y turned by Lcl Rotation about Y."""
    ry = math.radians(CAMERA["rotation"][1])
    assert CAMERA["rotation"][0] == 0 and CAMERA["rotation"][2] == 0
    forward = (math.cos(ry), 0.0, -math.sin(ry))
    pos = CAMERA["translation"]
    target = tuple(pos[k] + forward[k] for k in range(3))
    return pos, target, (0.0, 1.0, 0.0)


def clean(v):
    """Rounds away floating-point noise such as cos(90 deg) = 6e-17."""
    return tuple(0.0 if abs(x) < 1e-12 else round(x, 12) for x in v)


def write_fbx():
    check_geometry()
    w = Writer()
    w.line("; FBX 7.4.0 project file")
    w.line("; Written by scripts/make-test-fbx.py (symphong) for tests/test_assimp.cpp; edit the script, not this file.")
    w.line("; ----------------------------------------------------")
    w.line()

    # Header.
    w.block("FBXHeaderExtension: ")
    w.line("FBXHeaderVersion: 1003")
    w.line("FBXVersion: 7400")
    w.block("CreationTimeStamp: ")
    for key, value in (("Version", 1000), ("Year", 2024), ("Month", 1), ("Day", 1), ("Hour", 0), ("Minute", 0),
                       ("Second", 0), ("Millisecond", 0)):
        w.line(f"{key}: {value}")
    w.end()
    w.line('Creator: "symphong scripts/make-test-fbx.py"')
    w.block('SceneInfo: "SceneInfo::GlobalInfo", "UserData"')
    w.line('Type: "UserData"')
    w.line("Version: 100")
    w.block("MetaData: ")
    w.line("Version: 100")
    w.line('Title: "symphong FBX test box"')
    w.line('Subject: ""')
    w.line('Author: ""')
    w.line('Keywords: ""')
    w.line('Revision: ""')
    w.line('Comment: "A 2 x 1 x 3 box with a lamp on top, a camera and a point light"')
    w.end()
    w.props([
        prop("DocumentUrl", "KString", "Url", "", "box.fbx"),
        prop("SrcDocumentUrl", "KString", "Url", "", "box.fbx"),
        prop("Original|ApplicationName", "KString", "", "", "make-test-fbx.py"),
    ])
    w.end()
    w.end()
    w.line('FileId: "symphong-test-box"')
    w.line('CreationTime: "2024-01-01 00:00:00:000"')
    w.line('Creator: "symphong scripts/make-test-fbx.py"')

    # Global settings: y up, right-handed, metres.
    w.block("GlobalSettings: ")
    w.line("Version: 1000")
    w.props([
        prop("UpAxis", "int", "Integer", "", 1),
        prop("UpAxisSign", "int", "Integer", "", 1),
        prop("FrontAxis", "int", "Integer", "", 2),
        prop("FrontAxisSign", "int", "Integer", "", 1),
        prop("CoordAxis", "int", "Integer", "", 0),
        prop("CoordAxisSign", "int", "Integer", "", 1),
        prop("OriginalUpAxis", "int", "Integer", "", 1),
        prop("OriginalUpAxisSign", "int", "Integer", "", 1),
        prop("UnitScaleFactor", "double", "Number", "", UNIT_SCALE_FACTOR),
        prop("OriginalUnitScaleFactor", "double", "Number", "", UNIT_SCALE_FACTOR),
        prop("AmbientColor", "ColorRGB", "Color", "", 0, 0, 0),
        prop("DefaultCamera", "KString", "", "", "Camera"),
        prop("TimeMode", "enum", "", "", 6),
        prop("TimeSpanStart", "KTime", "Time", "", 0),
        prop("TimeSpanStop", "KTime", "Time", "", 46186158000),
        prop("CustomFrameRate", "double", "Number", "", -1),
    ])
    w.end()
    w.line()

    w.block("Documents: ")
    w.line("Count: 1")
    w.block(f'Document: {ID_DOCUMENT}, "Scene", "Scene"')
    w.props([prop("SourceObject", "object", "", ""), prop("ActiveAnimStackName", "KString", "", "", "")])
    w.line("RootNode: 0")
    w.end()
    w.end()
    w.line()
    w.block("References: ")
    w.end()
    w.line()

    # Definitions: object counts and property templates (defaults for properties an object omits).
    w.block("Definitions: ")
    w.line("Version: 100")
    w.line("Count: 6")
    w.block('ObjectType: "GlobalSettings"')
    w.line("Count: 1")
    w.end()
    w.block('ObjectType: "Model"')
    w.line("Count: 3")
    w.block('PropertyTemplate: "FbxNode"')
    w.props([
        prop("RotationOrder", "enum", "", "", 0),
        prop("InheritType", "enum", "", "", 0),
        prop("Lcl Translation", "Lcl Translation", "", "A", 0, 0, 0),
        prop("Lcl Rotation", "Lcl Rotation", "", "A", 0, 0, 0),
        prop("Lcl Scaling", "Lcl Scaling", "", "A", 1, 1, 1),
        prop("Visibility", "Visibility", "", "A", 1),
    ])
    w.end()
    w.end()
    w.block('ObjectType: "Geometry"')
    w.line("Count: 1")
    w.block('PropertyTemplate: "FbxMesh"')
    w.props([
        prop("Color", "ColorRGB", "Color", "", 0.8, 0.8, 0.8),
        prop("Primary Visibility", "bool", "", "", 1),
        prop("Casts Shadows", "bool", "", "", 1),
        prop("Receive Shadows", "bool", "", "", 1),
    ])
    w.end()
    w.end()
    w.block('ObjectType: "Material"')
    w.line("Count: 2")
    w.block('PropertyTemplate: "FbxSurfacePhong"')
    w.props([
        prop("ShadingModel", "KString", "", "", "Phong"),
        prop("MultiLayer", "bool", "", "", 0),
        color("EmissiveColor", (0, 0, 0)),
        number("EmissiveFactor", 1),
        color("AmbientColor", (0.2, 0.2, 0.2)),
        number("AmbientFactor", 1),
        color("DiffuseColor", (0.8, 0.8, 0.8)),
        number("DiffuseFactor", 1),
        color("TransparentColor", (0, 0, 0)),
        number("TransparencyFactor", 0),
        color("SpecularColor", (0.2, 0.2, 0.2)),
        number("SpecularFactor", 1),
        number("ShininessExponent", 20),
        color("ReflectionColor", (0, 0, 0)),
        number("ReflectionFactor", 1),
    ])
    w.end()
    w.end()
    w.block('ObjectType: "NodeAttribute"')
    w.line("Count: 2")
    w.block('PropertyTemplate: "FbxCamera"')
    w.props([
        prop("Position", "Vector", "", "A", 0, 0, -50),
        prop("UpVector", "Vector", "", "A", 0, 1, 0),
        prop("InterestPosition", "Vector", "", "A", 0, 0, 0),
        prop("AspectWidth", "double", "Number", "", 320),
        prop("AspectHeight", "double", "Number", "", 200),
        prop("ApertureMode", "enum", "", "", 2),
        prop("FieldOfView", "FieldOfView", "", "A", 25.114999771118164),
        prop("NearPlane", "double", "Number", "", 10),
        prop("FarPlane", "double", "Number", "", 4000),
    ])
    w.end()
    w.block('PropertyTemplate: "FbxLight"')
    w.props([
        prop("LightType", "enum", "", "", 0),
        color("Color", (1, 1, 1)),
        number("Intensity", 100),
        prop("DecayType", "enum", "", "", 0),
        prop("DecayStart", "double", "Number", "", 0),
        prop("CastShadows", "bool", "", "", 1),
    ])
    w.end()
    w.end()
    w.end()
    w.line()

    # Objects.
    w.block("Objects: ")

    # The box's geometry.
    w.block(f'Geometry: {ID_BOX_GEOMETRY}, "Geometry::Box", "Mesh"')
    w.raw(array("Vertices", [c for v in VERTICES for c in v]))
    indices = []
    for quad, _, _ in FACES:
        indices += list(quad[:-1]) + [-(quad[-1] + 1)]  # ones' complement marks a polygon's last vertex
    w.raw(array("PolygonVertexIndex", indices))
    w.line("GeometryVersion: 124")
    w.block("LayerElementNormal: 0")
    w.line("Version: 101")
    w.line('Name: ""')
    w.line('MappingInformationType: "ByPolygonVertex"')
    w.line('ReferenceInformationType: "Direct"')
    w.raw(array("Normals", [c for _, n, _ in FACES for _ in range(4) for c in n]))
    w.end()
    w.block("LayerElementMaterial: 0")
    w.line("Version: 101")
    w.line('Name: ""')
    w.line('MappingInformationType: "ByPolygon"')
    w.line('ReferenceInformationType: "IndexToDirect"')
    w.raw(array("Materials", [m for _, _, m in FACES]))
    w.end()
    w.block("Layer: 0")
    w.line("Version: 100")
    for kind in ("LayerElementNormal", "LayerElementMaterial"):
        w.block("LayerElement: ")
        w.line(f'Type: "{kind}"')
        w.line("TypedIndex: 0")
        w.end()
    w.end()
    w.end()

    # The camera's attribute.
    pos, target, up = camera_vectors()
    aspect = CAMERA["width"] / CAMERA["height"]
    fov_y = math.degrees(2 * math.atan(math.tan(math.radians(CAMERA["fov"]) / 2) / aspect))
    w.block(f'NodeAttribute: {ID_CAMERA_ATTR}, "NodeAttribute::Camera", "Camera"')
    w.props([
        prop("Position", "Vector", "", "A", *clean(pos)),
        prop("UpVector", "Vector", "", "A", *clean(up)),
        prop("InterestPosition", "Vector", "", "A", *clean(target)),
        prop("AspectWidth", "double", "Number", "", CAMERA["width"]),
        prop("AspectHeight", "double", "Number", "", CAMERA["height"]),
        prop("FilmAspectRatio", "double", "Number", "", aspect),
        prop("ApertureMode", "enum", "", "", 1),  # 1 = horizontal: FieldOfView is the horizontal angle
        prop("GateFit", "enum", "", "", 2),  # 2 = fit horizontal
        prop("FieldOfView", "FieldOfView", "", "A", CAMERA["fov"]),
        prop("FieldOfViewX", "FieldOfViewX", "", "A", CAMERA["fov"]),
        prop("FieldOfViewY", "FieldOfViewY", "", "A", fov_y),
        prop("NearPlane", "double", "Number", "", CAMERA["near"]),
        prop("FarPlane", "double", "Number", "", CAMERA["far"]),
    ])
    w.line('TypeFlags: "Camera"')
    w.line("GeometryVersion: 124")
    w.line(f"Position: {nums(clean(pos))}")
    w.line(f"Up: {nums(clean(up))}")
    w.line(f"LookAt: {nums(clean(target))}")
    w.line("ShowInfoOnMoving: 1")
    w.line("ShowAudio: 0")
    w.line("AudioColor: 0,1,0")
    w.line("CameraOrthoZoom: 1")
    w.end()

    # The light's attribute.
    w.block(f'NodeAttribute: {ID_LIGHT_ATTR}, "NodeAttribute::PointLight", "Light"')
    w.props([
        prop("LightType", "enum", "", "", 0),  # 0 = point
        color("Color", LIGHT["color"]),
        number("Intensity", LIGHT["intensity"]),
        prop("DecayType", "enum", "", "", 2),  # 2 = quadratic
        prop("DecayStart", "double", "Number", "", 1),
        prop("CastShadows", "bool", "", "", 1),
    ])
    w.line('TypeFlags: "Light"')
    w.line("GeometryVersion: 124")
    w.end()

    # The models.
    for model_id, name, kind, props in (
        (ID_BOX_MODEL, "Box", "Mesh", model_props()),
        (ID_CAMERA_MODEL, "Camera", "Camera", model_props(CAMERA["translation"], CAMERA["rotation"])),
        (ID_LIGHT_MODEL, "PointLight", "Light", model_props(LIGHT["translation"])),
    ):
        w.block(f'Model: {model_id}, "Model::{name}", "{kind}"')
        w.line("Version: 232")
        w.props(props)
        w.line("Shading: T")
        w.line('Culling: "CullingOff"')
        w.end()

    # The materials.
    for material_id, m in zip(ID_MATERIALS, MATERIALS):
        w.block(f'Material: {material_id}, "Material::{m["name"]}", ""')
        w.line("Version: 102")
        w.line('ShadingModel: "phong"')
        w.line("MultiLayer: 0")
        w.props([
            prop("ShadingModel", "KString", "", "", "phong"),
            color("EmissiveColor", m["emissive"]),
            number("EmissiveFactor", 1),
            color("AmbientColor", (0, 0, 0)),
            number("AmbientFactor", 1),
            color("DiffuseColor", m["diffuse"]),
            number("DiffuseFactor", 1),
            color("SpecularColor", m["specular"]),
            number("SpecularFactor", 1),
            number("ShininessExponent", m["shininess"]),
            number("Shininess", m["shininess"]),  # the legacy name, which the FBX SDK also writes
            color("TransparentColor", (0, 0, 0)),
            number("TransparencyFactor", 0),
            number("Opacity", 1),
            color("ReflectionColor", (0, 0, 0)),
            number("ReflectionFactor", 0),
            prop("Emissive", "Vector3D", "Vector", "", *m["emissive"]),
            prop("Diffuse", "Vector3D", "Vector", "", *m["diffuse"]),
            prop("Specular", "Vector3D", "Vector", "", *m["specular"]),
        ])
        w.end()
    w.end()
    w.line()

    # Connections: child, parent. Materials connect to the box's Model in the order of their indices.
    w.block("Connections: ")
    names = {0: "Model::RootNode", ID_BOX_MODEL: "Model::Box", ID_BOX_GEOMETRY: "Geometry::Box",
             ID_CAMERA_MODEL: "Model::Camera", ID_CAMERA_ATTR: "NodeAttribute::Camera",
             ID_LIGHT_MODEL: "Model::PointLight", ID_LIGHT_ATTR: "NodeAttribute::PointLight"}
    names.update({i: f"Material::{m['name']}" for i, m in zip(ID_MATERIALS, MATERIALS)})
    links = [(ID_BOX_MODEL, 0), (ID_CAMERA_MODEL, 0), (ID_LIGHT_MODEL, 0), (ID_BOX_GEOMETRY, ID_BOX_MODEL)]
    links += [(i, ID_BOX_MODEL) for i in ID_MATERIALS]
    links += [(ID_CAMERA_ATTR, ID_CAMERA_MODEL), (ID_LIGHT_ATTR, ID_LIGHT_MODEL)]
    for child, parent in links:
        w.line()
        w.line(f";{names[child]}, {names[parent]}")
        w.line(f'C: "OO",{child},{parent}')
    w.end()
    w.line()
    w.block("Takes: ")
    w.line('Current: ""')
    w.end()
    return w.text()


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else DEFAULT_OUT
    os.makedirs(os.path.dirname(os.path.abspath(out)), exist_ok=True)
    with open(out, "w", newline="\n") as f:
        f.write(write_fbx())
    print(out)


if __name__ == "__main__":
    main()
