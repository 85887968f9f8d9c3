#!/usr/bin/env python3
"""fuzz/make_corpus.py — prepares the seed corpora of the fuzz targets in OUT/<target>/ (scripts/fuzz.sh
passes build/fuzz/corpus, which is not committed and keeps what earlier campaigns added). Sources, each
put in the target's input layout (fuzz/*.cpp say what that is):

- fuzz/seeds/<target>/: the small hand-made inputs (fuzz/make_seeds.py writes them);
- tests/data/fuzz/<target>/: the regression inputs of earlier findings;
- fuzz_obj: every .obj of ../shared/scenes and scenes/ (and below) up to 256 KB (the bunny is left out), each
  followed by its first `mtllib` when that file is beside it, and the OBJ and MTL string literals of
  tests/*.cpp (an OBJ with a `mtllib` paired with each MTL);
- fuzz_json: scenes/*.json, as they are and with their "obj" pointed at the floor.obj and lamp.obj that
  fuzz_json writes beside its input; the JSON literals of tests/*.cpp (a "lights" list put into a scene
  on floor.obj) and the json blocks of docs/scene-format.md (fragments put into a scene);
- fuzz_assimp: the mesh files on disk under tests/ and scenes/ (and docs/images/), the glTF literals of tests/*.cpp, and
  scenes/cornell-classic.obj exported by the assimp command line tool (when it is there) as glTF, GLB,
  PLY (text and binary), Collada, 3DS and FBX;
- fuzz_texture: the image files on disk under tests/ and scenes/ and in docs/images/ (up to 64 KB each);
- fuzz_ply: the .ply files on disk under tests/ and scenes/ (up to 256 KB), as they are;
- fuzz_settings: the "render" objects of scenes/*.json and of the JSON literals of tests/*.cpp;
- fuzz_gltf_ext: the "materials" of the .gltf files on disk under tests/ and scenes/ and of the glTF
  literals of tests/*.cpp;
- fuzz_checkpoint: its seeds only (fuzz/make_seeds.py writes checkpoints with their checksums).

Files are named by their source and a content hash, so rerunning adds nothing twice.
Usage: python3 fuzz/make_corpus.py OUT
"""
import glob
import hashlib
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import warnings

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHARED = os.path.normpath(os.path.join(ROOT, "..", "shared", "scenes"))
OUT = sys.argv[1]
SEP = b"#==MTL==\n"
EXT = {".gltf": 0, ".glb": 1, ".ply": 2, ".fbx": 3, ".dae": 4, ".3ds": 5}
TARGETS = ["fuzz_obj", "fuzz_json", "fuzz_assimp", "fuzz_texture", "fuzz_ply", "fuzz_checkpoint", "fuzz_settings", "fuzz_gltf_ext"]
added = {t: 0 for t in TARGETS}


def put(target, label, data):
    if isinstance(data, str):
        data = data.encode()
    d = os.path.join(OUT, target)
    os.makedirs(d, exist_ok=True)
    label = re.sub(r"[^A-Za-z0-9._-]+", "_", label)[-60:]
    path = os.path.join(d, "%s-%s" % (label, hashlib.sha1(data).hexdigest()[:12]))
    if not os.path.exists(path):
        with open(path, "wb") as f:
            f.write(data)
        added[target] += 1


def rel(path):
    return os.path.relpath(path, ROOT)


for t in TARGETS:
    os.makedirs(os.path.join(OUT, t), exist_ok=True)
    for src in (os.path.join(ROOT, "fuzz", "seeds", t), os.path.join(ROOT, "tests", "data", "fuzz", t)):
        for f in sorted(glob.glob(os.path.join(src, "*"))):
            if os.path.isfile(f):
                put(t, rel(f), open(f, "rb").read())

# ---- string literals of the tests -----------------------------------------------------------------
raw_literals, c_literals = [], []
for f in sorted(glob.glob(os.path.join(ROOT, "tests", "*.cpp"))):
    text = open(f, encoding="utf-8", errors="replace").read()
    raw_literals += re.findall(r'R"\((.*?)\)"', text, re.S)
    for m in re.findall(r'"((?:[^"\\\n]|\\.)*)"', text):
        try:
            # A C escape that Python lacks (\* in a test's pattern) decodes as itself, with a DeprecationWarning
            # that only clutters the campaign's log.
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", DeprecationWarning)
                c_literals.append(bytes(m, "utf-8").decode("unicode_escape"))
        except UnicodeDecodeError:
            pass

# ---- fuzz_obj -------------------------------------------------------------------------------------
def first_mtllib(obj_bytes):
    for line in obj_bytes.decode("latin-1").splitlines():
        w = line.split()
        if len(w) >= 2 and w[0] == "mtllib":
            return w[1]
    return None


objs = sorted(glob.glob(os.path.join(SHARED, "**", "*.obj"), recursive=True) +
              glob.glob(os.path.join(ROOT, "scenes", "**", "*.obj"), recursive=True))
for f in objs:
    if os.path.getsize(f) > 256 * 1024:
        continue
    data = open(f, "rb").read()
    lib = first_mtllib(data)
    mtl = os.path.join(os.path.dirname(f), lib) if lib else None
    if mtl and os.path.isfile(mtl):
        data = data + (b"" if data.endswith(b"\n") else b"\n") + SEP + open(mtl, "rb").read()
    put("fuzz_obj", os.path.basename(f), data)
obj_lits = [s for s in c_literals if re.search(r"(^|\n)v ", s) and re.search(r"(^|\n)f ", s)]
mtl_lits = [s for s in c_literals if "newmtl" in s]
for s in obj_lits:
    put("fuzz_obj", "tests-literal.obj", s)
    if "mtllib" in s:
        for m in mtl_lits:
            put("fuzz_obj", "tests-literal-mtl.obj", s + ("" if s.endswith("\n") else "\n") + SEP.decode() + m)

# ---- fuzz_json ------------------------------------------------------------------------------------
def scene_json(value):
    return json.dumps(value)


for f in sorted(glob.glob(os.path.join(ROOT, "scenes", "*.json"))):
    text = open(f, "rb").read()
    put("fuzz_json", os.path.basename(f), text)
    try:
        doc = json.loads(text)
    except ValueError:
        continue
    if isinstance(doc, dict) and isinstance(doc.get("render"), dict):
        put("fuzz_settings", os.path.basename(f) + "-render", json.dumps(doc["render"]))
    if isinstance(doc, dict) and "obj" in doc:
        for target in ("floor.obj", "lamp.obj"):
            d = dict(doc, obj=target)
            d.pop("materials", None)
            put("fuzz_json", os.path.basename(f) + "-" + target, scene_json(d))
for s in raw_literals:
    try:
        doc = json.loads(s)
    except ValueError:
        continue
    if isinstance(doc, dict) and "asset" in doc:
        put("fuzz_assimp", "tests-literal.gltf", bytes([EXT[".gltf"]]) + s.encode())
        if isinstance(doc.get("materials"), list):
            put("fuzz_gltf_ext", "tests-literal-materials.json", json.dumps(doc["materials"]))
    elif isinstance(doc, list):
        put("fuzz_json", "tests-literal-lights.json", '{"obj": "floor.obj", "lights": ' + s + "}")
    else:
        put("fuzz_json", "tests-literal.json", s)
        if isinstance(doc, dict) and isinstance(doc.get("render"), dict):
            put("fuzz_settings", "tests-literal-render.json", json.dumps(doc["render"]))
        if isinstance(doc, dict) and doc.get("obj") not in (None, "floor.obj"):
            put("fuzz_json", "tests-literal-floor.json", scene_json(dict(doc, obj="floor.obj")))
doc_md = open(os.path.join(ROOT, "docs", "scene-format.md"), encoding="utf-8").read()
for block in re.findall(r"```json\n(.*?)```", doc_md, re.S):
    for candidate in (block, "{" + block + "}", '{"builtin": "cornell", ' + block + "}", '{"obj": "floor.obj", ' + block + "}"):
        try:
            doc = json.loads(candidate)
        except ValueError:
            continue
        if isinstance(doc, dict) and "obj" in doc and doc["obj"] != "floor.obj":
            doc = dict(doc, obj="floor.obj")
            doc.pop("materials", None)
            candidate = scene_json(doc)
        put("fuzz_json", "scene-format.md.json", candidate)

# ---- fuzz_assimp, fuzz_texture: files on disk under tests/ and scenes/, and in docs/images/ ----------------
# (docs/: only docs/images/ itself; docs/study/ holds a hundred near-identical renders)
on_disk = [os.path.join(ROOT, d, "**", "*") for d in ("tests", "scenes")] + [os.path.join(ROOT, "docs", "images", "*")]
for f in sorted(sum((glob.glob(g, recursive=True) for g in on_disk), [])):
    if not os.path.isfile(f) or os.sep + "fuzz" + os.sep in f:
        continue
    ext = os.path.splitext(f)[1].lower()
    if ext in EXT and os.path.getsize(f) <= 256 * 1024:
        put("fuzz_assimp", rel(f), bytes([EXT[ext]]) + open(f, "rb").read())
        if ext == ".ply":
            put("fuzz_ply", rel(f), open(f, "rb").read())
        if ext == ".gltf":
            try:
                mats = json.loads(open(f, "rb").read()).get("materials")
            except (ValueError, AttributeError):
                mats = None
            if isinstance(mats, list):
                put("fuzz_gltf_ext", rel(f) + "-materials", json.dumps(mats))
    elif ext in (".png", ".jpg", ".jpeg", ".hdr", ".exr", ".bmp", ".tga") and os.path.getsize(f) <= 64 * 1024:
        put("fuzz_texture", rel(f), bytes([1 if ext in (".hdr", ".exr") else 0]) + open(f, "rb").read())

if shutil.which("assimp"):
    src = os.path.join(ROOT, "scenes", "cornell-classic.obj")
    with tempfile.TemporaryDirectory() as tmp:
        for fmt, ext in (("gltf2", ".gltf"), ("glb2", ".glb"), ("ply", ".ply"), ("plyb", ".ply"), ("collada", ".dae"),
                         ("3ds", ".3ds"), ("fbx", ".fbx"), ("fbxa", ".fbx")):
            dst = os.path.join(tmp, "classic-" + fmt + ext)
            r = subprocess.run(["assimp", "export", src, dst, "-f" + fmt], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            if r.returncode != 0 or not os.path.exists(dst):
                continue
            data = open(dst, "rb").read()
            if ext == ".gltf":
                # The .gltf names its buffer "classic-gltf2.bin": inline it as a data URI, so the file stands alone.
                import base64
                doc = json.loads(data)
                for b in doc.get("buffers", []):
                    uri = b.get("uri", "")
                    if uri and not uri.startswith("data:") and os.path.exists(os.path.join(tmp, uri)):
                        b["uri"] = "data:application/octet-stream;base64," + base64.b64encode(open(os.path.join(tmp, uri), "rb").read()).decode()
                data = json.dumps(doc).encode()
            if len(data) <= 256 * 1024:
                put("fuzz_assimp", "cornell-classic-" + fmt + ext, bytes([EXT[ext]]) + data)

for t in TARGETS:
    n = len(os.listdir(os.path.join(OUT, t)))
    print("corpus %-13s %4d files (%d new)" % (t, n, added[t]))
