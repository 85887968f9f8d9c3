#!/usr/bin/env python3
"""fuzz/make_seeds.py — writes fuzz/seeds/<target>/, the small hand-made seed inputs of the fuzz targets
(committed; a few KB in all), standard library only: OBJ+MTL pairs in fuzz_obj's input layout (the OBJ,
a line "#==MTL==", the MTL), JSON scenes naming the files fuzz_json writes beside them, one-triangle
meshes in every Assimp format with fuzz_assimp's leading extension byte, and tiny images of every kind
the texture decoder reads (PNG of each colour type, 16-bit and interlaced; JPEG; BMP; TGA raw and RLE;
Radiance HDR flat and RLE; OpenEXR uncompressed half and float; PNM; GIF) with fuzz_texture's
leading encoding byte. The JPEG and the 3DS come from tools when they are there (a C compiler with
stb_image_write.h; the assimp command line) and are left out otherwise.

Usage: python3 fuzz/make_seeds.py [OUTPUT_DIR]   (default: fuzz/seeds beside this script)
The output is deterministic: rerunning it leaves the committed files as they are.
"""
import os
import shutil
import struct
import subprocess
import sys
import tempfile
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = sys.argv[1] if len(sys.argv) > 1 else os.path.join(HERE, "seeds")
SEP = "#==MTL==\n"
# fuzz_assimp: the first byte picks the extension, byte % 6.
EXT = {".gltf": 0, ".glb": 1, ".ply": 2, ".fbx": 3, ".dae": 4, ".3ds": 5}


def put(target, name, data):
    d = os.path.join(OUT, target)
    os.makedirs(d, exist_ok=True)
    if isinstance(data, str):
        data = data.encode()
    with open(os.path.join(d, name), "wb") as f:
        f.write(data)


# ---- fuzz_obj -------------------------------------------------------------------------------------
TRI = "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
put("fuzz_obj", "triangle.obj", TRI + "f 1 2 3\n")
put("fuzz_obj", "quad-mtl.obj", "mtllib m.mtl\n" + TRI + "v 1 1 0\nusemtl a\nf 1 2 4 3\n" + SEP +
    "newmtl a\nKd 0.5 0.4 0.3\nKs 0.2 0.2 0.2\nNs 30\n")
put("fuzz_obj", "normals-uv.obj", "mtllib in.mtl\n" + TRI + "vt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\nvn 0 0.5 0.5\n"
    "o thing\ng part\ns 1\nusemtl lamp\nf 1/1/1 2/2/1 3/3/2\nf -3/-3/-2 -2/-2/-1 -1/-1/-1\n" + SEP +
    "# lamp\nnewmtl lamp\nKa 0 0 0\nKd 0 0 0\nKe 4 4 4\nillum 2\nd 1\nTr 0\nNi 1.5\nmap_Kd tex.png\n"
    "newmtl  spaced \nKd 0.2 0.2 0.2\n")
put("fuzz_obj", "polygon-relative.obj", "v 0 0 0\nv 2 0 0\nv 3 1 0\nv 2 2 0\nv 0 2 0\nv -1 1 0\nf -6 -5 -4 -3 -2 -1\n"
    "l 1 2\np 3\nf 1 2 3 4\n")
put("fuzz_obj", "crlf-comments.obj", "# comment\r\nmtllib m.mtl\r\nv 0 0 0 1\r\nv 1 0 0\r\nv 0 1 0 # trailing\r\n"
    "usemtl undefined\r\nf 1 2 3\r\n" + SEP + "newmtl a\r\nKd 1 1 1\r\nKs 0.5 0.5 0.5\r\n")
put("fuzz_obj", "glossy-sum.obj", "mtllib g.mtl\n" + TRI + "usemtl g\nf 1 2 3\n" + SEP +
    "newmtl g\nKd 0.8 0.8 0.8\nKs 0.8 0.8 0.8\nNs 1000\nKe 0 0 0\n")

# ---- fuzz_json ------------------------------------------------------------------------------------
put("fuzz_json", "builtin.json", '{"builtin": "cornell"}')
put("fuzz_json", "builtin-all.json", '{"builtin": "cornell", "name": "x", "environment": [0.1, 0.2, 0.3],'
    ' "camera": {"position": [278, 273, -800], "target": [278, 273, 0], "up": [0, 1, 0], "fov": 39.3},'
    ' "materials": {"white": {"kd": 0.5, "ks": [0.1, 0.1, 0.1], "ns": 20, "ke": 0}, "tallBlock": {"ns": 2}}}')
put("fuzz_json", "floor-lights.json", '{"obj": "floor.obj", "lights": ['
    '{"type": "point", "position": [0, 1.9, 0], "intensity": [5, 5, 4]},'
    '{"type": "spot", "position": [1, 2, 0], "target": [1, 0, 0], "intensity": 20, "angle": 30, "inner": 25},'
    '{"type": "spot", "position": [1, 2, 0], "direction": [0, -1, 0], "intensity": 2},'
    '{"type": "directional", "direction": [-0.3, -1, 0.2], "irradiance": 2},'
    '{"type": "quad", "corner": [-0.5, 1.98, -0.5], "edge1": [1, 0, 0], "edge2": [0, 0, 1], "radiance": 10}],'
    ' "materials": {"floor": {"kd": [0.3, 0.3, 0.3]}}}')
put("fuzz_json", "lamp.json", '{"obj": "lamp.obj", "camera": {"position": [0, 5, 5], "target": [0, 0, 0]},'
    ' "materials": {"lamp": {"ke": [1, 2, 3]}}}')
put("fuzz_json", "mesh-gltf.json", '{"mesh": "tri.gltf", "materials": {"metal": {"ks": 0.1}}, "environment": 1}')
put("fuzz_json", "mesh-ply.json", '{"mesh": "tri.ply", "camera": {"fov": 60}}')
put("fuzz_json", "mesh-obj.json", '{"mesh": "floor.obj", "name": "m", "environment": 0}')

# ---- fuzz_assimp ----------------------------------------------------------------------------------
POS = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
GLTF = ('{"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0, 1, 2]}],'
        ' "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_emissive_strength"],'
        ' "nodes": [{"mesh": 0, "rotation": [0, 0, 0, 1], "scale": [1, 2, 1]}, {"camera": 0, "translation": [0, 1, 5]},'
        ' {"extensions": {"KHR_lights_punctual": {"light": 0}}, "translation": [0, 3, 0], "children": []}],'
        ' "cameras": [{"type": "perspective", "perspective": {"yfov": 0.6, "aspectRatio": 1.5, "znear": 0.1}}],'
        ' "extensions": {"KHR_lights_punctual": {"lights": [{"type": "spot", "color": [1, 1, 1], "intensity": 10,'
        ' "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.5}}]}},'
        ' "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0, "mode": 4}]}],'
        ' "materials": [{"name": "metal", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.6, 0.4, 1],'
        ' "metallicFactor": 0.25, "roughnessFactor": 0.5}, "emissiveFactor": [1, 0.5, 0],'
        ' "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4}}}],'
        ' "buffers": [{"byteLength": 44%s}],'
        ' "bufferViews": [{"buffer": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 6}],'
        ' "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},'
        ' {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}]}')
BIN = POS + struct.pack("<3H", 0, 1, 2) + b"\0\0"
import base64
put("fuzz_assimp", "tri.gltf", bytes([EXT[".gltf"]]) + (GLTF % (', "uri": "data:application/octet-stream;base64,' +
                                                               base64.b64encode(BIN).decode() + '"')).encode())
js = (GLTF % "").encode()
js += b" " * (-len(js) % 4)
glb = b"glTF" + struct.pack("<II", 2, 12 + 8 + len(js) + 8 + len(BIN)) + struct.pack("<I", len(js)) + b"JSON" + js + \
    struct.pack("<I", len(BIN)) + b"BIN\0" + BIN
put("fuzz_assimp", "tri.glb", bytes([EXT[".glb"]]) + glb)
PLYHEAD = "ply\nformat {}\ncomment tiny\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n" \
          "property float nx\nproperty float ny\nproperty float nz\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n" \
          "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
put("fuzz_assimp", "tri-ascii.ply", bytes([EXT[".ply"]]) + (PLYHEAD.format("ascii 1.0") +
    "0 0 0 0 0 1 255 0 0\n1 0 0 0 0 1 0 255 0\n0 1 0 0 0 1 0 0 255\n3 0 1 2\n").encode())
verts = b"".join(struct.pack("<6f3B", *p, 0, 0, 1, 200, 100, 50) for p in ((0, 0, 0), (1, 0, 0), (0, 1, 0)))
put("fuzz_assimp", "tri-binary.ply", bytes([EXT[".ply"]]) + PLYHEAD.format("binary_little_endian 1.0").encode() + verts +
    struct.pack("<B3i", 3, 0, 1, 2))
DAE = """<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
 <asset><unit name="meter" meter="1"/><up_axis>Y_UP</up_axis></asset>
 <library_cameras><camera id="cam"><optics><technique_common><perspective><xfov>40</xfov><aspect_ratio>1.5</aspect_ratio><znear>0.1</znear><zfar>100</zfar></perspective></technique_common></optics></camera></library_cameras>
 <library_lights><light id="lamp"><technique_common><point><color>1 1 1</color><constant_attenuation>1</constant_attenuation></point></technique_common></light></library_lights>
 <library_effects><effect id="fx"><profile_COMMON><technique sid="common"><phong>
  <emission><color>0 0 0 1</color></emission><diffuse><color>0.5 0.4 0.3 1</color></diffuse>
  <specular><color>0.2 0.2 0.2 1</color></specular><shininess><float>20</float></shininess></phong></technique></profile_COMMON></effect></library_effects>
 <library_materials><material id="mat" name="mat"><instance_effect url="#fx"/></material></library_materials>
 <library_geometries><geometry id="tri"><mesh>
  <source id="pos"><float_array id="pa" count="9">0 0 0 1 0 0 0 1 0</float_array>
   <technique_common><accessor source="#pa" count="3" stride="3"><param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common></source>
  <vertices id="v"><input semantic="POSITION" source="#pos"/></vertices>
  <triangles count="1" material="m"><input semantic="VERTEX" source="#v" offset="0"/><p>0 1 2</p></triangles>
 </mesh></geometry></library_geometries>
 <library_visual_scenes><visual_scene id="s">
  <node id="n"><matrix>1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1</matrix><instance_geometry url="#tri"><bind_material><technique_common><instance_material symbol="m" target="#mat"/></technique_common></bind_material></instance_geometry></node>
  <node id="c"><translate>0 0.5 4</translate><instance_camera url="#cam"/></node>
  <node id="l"><translate>0 3 0</translate><instance_light url="#lamp"/></node>
 </visual_scene></library_visual_scenes>
 <scene><instance_visual_scene url="#s"/></scene>
</COLLADA>
"""
put("fuzz_assimp", "tri.dae", bytes([EXT[".dae"]]) + DAE.encode())
# 3DS and an ASCII FBX through Assimp's own exporters, when the command line tool is there.
if shutil.which("assimp"):
    with tempfile.TemporaryDirectory() as tmp:
        src = os.path.join(tmp, "tri.obj")
        with open(src, "w") as f:
            f.write("mtllib tri.mtl\n" + TRI + "usemtl a\nf 1 2 3\n")
        with open(os.path.join(tmp, "tri.mtl"), "w") as f:
            f.write("newmtl a\nKd 0.5 0.5 0.5\nKs 0.1 0.1 0.1\nNs 10\n")
        for fmt, ext in (("3ds", ".3ds"), ("fbxa", ".fbx")):
            dst = os.path.join(tmp, "out" + ext)
            if subprocess.run(["assimp", "export", src, dst, "-f" + fmt], stdout=subprocess.DEVNULL,
                              stderr=subprocess.DEVNULL).returncode == 0 and os.path.exists(dst):
                data = open(dst, "rb").read()
                if fmt == "fbxa":  # drop the creation time so that the file is reproducible
                    data = b"\n".join(l for l in data.split(b"\n") if b"CreationTime" not in l and b"TimeStamp" not in l
                                      and b"Year" not in l and b"Month" not in l and b"Day" not in l and b"Hour" not in l
                                      and b"Minute" not in l and b"Second" not in l and b"Millisecond" not in l)
                put("fuzz_assimp", "tri" + ext, bytes([EXT[ext]]) + data)

# ---- fuzz_texture ---------------------------------------------------------------------------------
# First byte: bit 0 picks the encoding (0 sRGB, 1 linear); the rest is the image file.
def tex(name, data, linear=False):
    put("fuzz_texture", name, bytes([1 if linear else 0]) + data)


def chunk(kind, data):
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xffffffff)


def png(w, h, depth, ctype, rows, extra=b"", interlace=0, filters=None):
    raw = b"".join(bytes([filters[i % len(filters)] if filters else 0]) + r for i, r in enumerate(rows))
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, depth, ctype, 0, 0, interlace)) + extra + \
        chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")


tex("rgb8.png", png(2, 2, 8, 2, [bytes([255, 0, 0, 0, 255, 0]), bytes([0, 0, 255, 128, 128, 128])]))
tex("gray1.png", png(1, 1, 8, 0, [b"\x80"]), linear=True)
tex("rgba8-filters.png", png(3, 3, 8, 6, [bytes(range(i * 12, i * 12 + 12)) for i in range(3)], filters=[1, 2, 3, 4]))
tex("gray-alpha.png", png(2, 1, 8, 4, [bytes([10, 255, 200, 0])]))
tex("rgb16.png", png(2, 1, 16, 2, [struct.pack(">6H", 65535, 0, 30000, 1, 2, 3)]))
tex("palette.png", png(2, 2, 8, 3, [b"\x00\x01", b"\x01\x00"], extra=chunk(b"PLTE", bytes([255, 0, 0, 0, 0, 255])) +
                   chunk(b"tRNS", b"\x80")))
tex("gray4bit.png", png(4, 1, 4, 0, [b"\x12\x34"]))
# Adam7-interlaced 3x3 RGB: the seven passes' sub-images (rows of the sizes that pass has).
passes = [(1, 1), (0, 0), (0, 0), (1, 1), (2, 1), (1, 2), (3, 1)]  # (w, h) of each Adam7 pass of a 3x3 image
rows = []
for (pw, ph) in passes:
    for _ in range(ph):
        rows.append(bytes([0]) + bytes([50, 100, 150]) * pw)
raw = b"".join(rows)
tex("interlaced.png", b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", 3, 3, 8, 2, 0, 0, 1)) +
    chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))
# BMP, 24-bit, 2x2 (rows bottom-up, padded to 4 bytes).
pix = bytes([0, 0, 255, 0, 255, 0, 0, 0]) + bytes([255, 0, 0, 255, 255, 255, 0, 0])
tex("rgb24.bmp", b"BM" + struct.pack("<IHHI", 14 + 40 + len(pix), 0, 0, 54) +
    struct.pack("<IiiHHIIiiII", 40, 2, 2, 1, 24, 0, len(pix), 2835, 2835, 0, 0) + pix)
# BMP, 8-bit palette, 2x1.
pal = bytes([0, 0, 0, 0, 255, 255, 255, 0])
tex("pal8.bmp", b"BM" + struct.pack("<IHHI", 14 + 40 + 8 + 4, 0, 0, 14 + 40 + 8) +
    struct.pack("<IiiHHIIiiII", 40, 2, 1, 1, 8, 0, 4, 0, 0, 2, 0) + pal + b"\x00\x01\x00\x00")
# TGA: uncompressed true colour 2x1, and RLE 4x1.
tex("raw.tga", struct.pack("<BBBHHBHHHHBB", 0, 0, 2, 0, 0, 0, 0, 0, 2, 1, 24, 0) + bytes([1, 2, 3, 4, 5, 6]))
tex("rle.tga", struct.pack("<BBBHHBHHHHBB", 0, 0, 10, 0, 0, 0, 0, 0, 4, 1, 32, 8) + bytes([0x83, 9, 8, 7, 255]))
# Radiance HDR: flat 2x2, and new-style RLE 8x1.
hdrhead = b"#?RADIANCE\n# tiny\nFORMAT=32-bit_rle_rgbe\nEXPOSURE=1.0\n\n"
tex("flat.hdr", hdrhead + b"-Y 2 +X 2\n" + bytes([128, 64, 32, 129, 0, 0, 0, 0, 255, 255, 255, 128, 1, 2, 3, 140]))
line = bytes([2, 2, 0, 8])
for comp in (100, 50, 25, 129):
    line += bytes([128 + 8, comp])  # a run of 8
tex("rle.hdr", hdrhead + b"-Y 1 +X 8\n" + line)


def exr(w, h, ptype, compression=0, channels="BGR"):
    def attr(name, kind, value):
        return name.encode() + b"\0" + kind.encode() + b"\0" + struct.pack("<i", len(value)) + value
    chl = b"".join(c.encode() + b"\0" + struct.pack("<iB3xii", ptype, 0, 1, 1) for c in channels) + b"\0"
    head = b"\x76\x2f\x31\x01" + struct.pack("<I", 2)
    head += attr("channels", "chlist", chl) + attr("compression", "compression", bytes([compression]))
    head += attr("dataWindow", "box2i", struct.pack("<4i", 0, 0, w - 1, h - 1))
    head += attr("displayWindow", "box2i", struct.pack("<4i", 0, 0, w - 1, h - 1))
    head += attr("lineOrder", "lineOrder", b"\0") + attr("pixelAspectRatio", "float", struct.pack("<f", 1))
    head += attr("screenWindowCenter", "v2f", struct.pack("<2f", 0, 0)) + attr("screenWindowWidth", "float", struct.pack("<f", 1))
    head += b"\0"
    size = 2 if ptype == 1 else 4
    blocks = []
    for y in range(h):
        data = b""
        for ci, _ in enumerate(channels):
            for x in range(w):
                v = 0.25 * (x + 1) + 0.5 * y + 0.1 * ci
                data += struct.pack("<e", v) if ptype == 1 else struct.pack("<f", v)
        blocks.append(struct.pack("<ii", y, len(data)) + data)
    offset = len(head) + 8 * h
    table = b""
    for b in blocks:
        table += struct.pack("<Q", offset)
        offset += len(b)
    return head + table + b"".join(blocks)


tex("half-rgb.exr", exr(2, 2, 1), linear=True)
tex("float-rgba.exr", exr(3, 1, 2, channels="ABGR"), linear=True)
tex("half-y.exr", exr(1, 2, 1, channels="Y"), linear=True)
tex("p6.ppm", b"P6\n# c\n2 1\n255\n" + bytes([255, 0, 0, 0, 255, 0]))
tex("p5.pgm", b"P5 1 1 255 " + b"\x40")
tex("one.gif", bytes.fromhex("47494638396101000100800000ffffff00000021f90401000000002c00000000010001000002024401003b"))
# JPEG through stb_image_write, when a C compiler is there.
cc = shutil.which("cc") or shutil.which("clang") or shutil.which("gcc")
if cc and os.path.exists("/usr/include/stb/stb_image_write.h"):
    with tempfile.TemporaryDirectory() as tmp:
        c = os.path.join(tmp, "w.c")
        with open(c, "w") as f:
            f.write('#define STB_IMAGE_WRITE_IMPLEMENTATION\n#include <stb/stb_image_write.h>\n'
                    'int main(int argc, char** argv) { unsigned char p[8 * 8 * 3]; for (int i = 0; i < 8 * 8 * 3; ++i) p[i] = (unsigned char)(i * 7);\n'
                    '  unsigned char g[16 * 2]; for (int i = 0; i < 32; ++i) g[i] = (unsigned char)(i * 8);\n'
                    '  return !(stbi_write_jpg(argv[1], 8, 8, 3, p, 75) && stbi_write_jpg(argv[2], 16, 2, 1, g, 90)); }\n')
        exe = os.path.join(tmp, "w")
        if subprocess.run([cc, "-O1", "-o", exe, c, "-lm"], stderr=subprocess.DEVNULL).returncode == 0:
            a, b = os.path.join(tmp, "a.jpg"), os.path.join(tmp, "b.jpg")
            if subprocess.run([exe, a, b]).returncode == 0:
                tex("rgb.jpg", open(a, "rb").read())
                tex("gray.jpg", open(b, "rb").read(), linear=True)

# ---- fuzz_ply: symphong's own PLY reader ----------------------------------------------------------
PLY_V = "ply\nformat {fmt} 1.0\ncomment seed\nelement vertex {n}\nproperty float x\nproperty float y\nproperty float z\n"
put("fuzz_ply", "tri-ascii.ply", PLY_V.format(fmt="ascii", n=3) +
    "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
put("fuzz_ply", "quad-normals-uv-ascii.ply", "ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty double y\n"
    "property double z\nproperty float nx\nproperty float ny\nproperty float nz\nproperty float s\nproperty float t\n"
    "element face 1\nproperty list uint8 uint32 vertex_index\nend_header\n"
    "0 0 0 0 0 1 0 0\n1 0 0 0 0 1 1 0\n1 1 0 0 0 1 1 1\n0 1 0 0 0 1 0 1\n4 0 1 2 3\n")
put("fuzz_ply", "strips-restart-ascii.ply", PLY_V.format(fmt="ascii", n=5) +
    "property uchar red\nelement tristrips 1\nproperty list int int vertex_indices\nelement extra 1\nproperty short w\nend_header\n"
    "0 0 0 1\n1 0 0 2\n0 1 0 3\n1 1 0 4\n2 1 0 5\n6 0 1 2 -1 2 3\n7\n")
verts = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
put("fuzz_ply", "tri-binary-le.ply", (PLY_V.format(fmt="binary_little_endian", n=3) +
    "element face 1\nproperty list uchar int vertex_indices\nend_header\n").encode() + verts + struct.pack("<B3i", 3, 0, 1, 2))
put("fuzz_ply", "tri-binary-be.ply", (PLY_V.format(fmt="binary_big_endian", n=3) +
    "element face 1\nproperty list uchar int vertex_indices\nend_header\n").encode() +
    struct.pack(">9f", 0, 0, 0, 1, 0, 0, 0, 1, 0) + struct.pack(">B3i", 3, 0, 1, 2))
put("fuzz_ply", "strip-binary-le.ply", ("ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float32 x\n"
    "property float32 y\nproperty float32 z\nproperty float32 u\nproperty float32 v\nelement tristrips 1\n"
    "property list int32 int32 vertex_indices\nend_header\n").encode() +
    struct.pack("<20f", 0, 0, 0, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 1, 1, 0, 1, 1) + struct.pack("<5i", 4, 0, 1, 2, 3))

# ---- fuzz_checkpoint: one flags byte (bit 0: the harness makes the checksum right), then the file ------
# The checksum is render/checkpoint.cpp's Hasher; the layout is render/checkpoint.h's.
M64 = (1 << 64) - 1


def ck_mix(h, w):
    h = ((h ^ w) * 0x9E3779B97F4A7C15) & M64
    return h ^ (h >> 29)


class CkHash:
    def __init__(self):
        self.lane = [1, 2, 3, 4]

    def add(self, b):
        i = 0
        while i + 32 <= len(b):
            for k in range(4):
                self.lane[k] = ck_mix(self.lane[k], struct.unpack_from("<Q", b, i + 8 * k)[0])
            i += 32
        while i + 8 <= len(b):
            self.lane[0] = ck_mix(self.lane[0], struct.unpack_from("<Q", b, i)[0])
            i += 8
        tail = int.from_bytes((b[i:] + b"\0" * 8)[:8], "little")
        self.lane[0] = ck_mix(self.lane[0], tail ^ ((len(b) - i) << 56))

    def value(self):
        h = 0x243F6A8885A308D3
        for l in self.lane:
            h = ck_mix(h, l)
        return h


def checkpoint(w, h, spp, tiles_done, settings=None, extra=None):
    import json as _json
    tiles = ((w + 15) // 16) * ((h + 15) // 16)
    px = w * h
    header = {"scene": "cornell", "scene_hash": "0123456789abcdef",
              "settings": settings if settings is not None else {"estimator": "phong", "sampler": "sobol", "spp": spp,
                                                                 "width": w, "height": h, "seed": 1, "max_depth": 16},
              "width": w, "height": h, "spp": spp, "samples_reached": tiles_done, "rays": 1000, "bad_samples": 0,
              "samples": px * tiles_done, "paths": px * tiles_done, "seconds": 0.5, "cpu_seconds": 0.9}
    header.update(extra or {})
    magic = b"symphong checkpoint 1\n"
    line = (_json.dumps(header, separators=(",", ":")) + "\n").encode()
    sections = [struct.pack("<%dI" % tiles, *([tiles_done] * tiles)),
                b"".join(struct.pack("<3d", 0.25 * tiles_done, 0.5 * tiles_done, 0.125 * (i % 7) * tiles_done) for i in range(px)),
                b"".join(struct.pack("<3d", 0.0625 * tiles_done, 0.25 * tiles_done, 0.01 * (i % 7) * tiles_done) for i in range(px)),
                b"".join(struct.pack("<d", 0.1 * tiles_done) for i in range(px))]
    hsh = CkHash()
    for part in [magic, line] + sections:
        hsh.add(part)
    return magic + line + b"".join(sections) + struct.pack("<Q", hsh.value())


put("fuzz_checkpoint", "4x3-spp8-fixed.ckpt", b"\x01" + checkpoint(4, 3, 8, 4))
put("fuzz_checkpoint", "4x3-spp8-as-written.ckpt", b"\x00" + checkpoint(4, 3, 8, 4))
put("fuzz_checkpoint", "17x2-two-tiles-fixed.ckpt", b"\x01" + checkpoint(17, 2, 4, 1))
put("fuzz_checkpoint", "2x2-finished-old-header.ckpt", b"\x01" + checkpoint(2, 2, 2, 2, extra={"paths": None, "cpu_seconds": None})
    .replace(b',"paths":null', b"").replace(b',"cpu_seconds":null', b""))
put("fuzz_checkpoint", "1x1-empty-settings.ckpt", b"\x01" + checkpoint(1, 1, 1, 0, settings={}))
# A header that claims a size the file does not have: 64x64 with the sections of 4x3.
put("fuzz_checkpoint", "header-claims-64x64.ckpt", b"\x00" + checkpoint(4, 3, 8, 4).replace(b'"width":4,"height":3', b'"width":64,"height":64'))

# An --splitting ears checkpoint (the ears header object, its factor and sum sections): the committed one of
# tests/data/checkpoints (three values a cell, written before the first hit's MIS share), as written, and
# with its header claiming four values a cell, the count of the writer now (the sections then too short).
with open(os.path.join(HERE, "..", "tests", "data", "checkpoints", "ears-three-values.ckpt"), "rb") as f:
    EARS_CKPT = f.read()
put("fuzz_checkpoint", "ears-three-values-as-written.ckpt", b"\x00" + EARS_CKPT)
put("fuzz_checkpoint", "ears-header-claims-four-values.ckpt",
    b"\x00" + EARS_CKPT.replace(b'"ears":{"epoch":2,', b'"ears":{"epoch":2,"factor_values":4,', 1))

# A small --splitting ears checkpoint made here (4x3 pixels, six factor cells of four values, six cells of sums):
# its sections of learned splitting fit libFuzzer's -max_len, unlike the committed one above, and with flags bit
# 0 the harness repairs the checksum over them too (fuzz_common.h earsSectionSizes), so that mutations reach
# the factors' and sums' checks and the epoch end that a resumed render runs on them (checkpointProblem).
# Cells: the Grid's levels start at 0, 64, 576 and 4672 (4^3, 8^3, 16^3, 32^3 cells); a section of sums is
# 37440 cells. Sums are CellSums: count, rays, then the values and squares as 128-bit fixed point (2^-40).
def ears_checkpoint():
    cells_per_section, finest = 37440, 4672
    factor_cells = [0, 64, 600, finest, finest + 1, finest + 1000]
    values = [(0.5, 0.75, 2.0, 0.25), (0.25, 0.5, 1.0, 0.0), (-1.0, -1.0, 4.0, 1.0), (0.125, 0.25, 8.0, 0.5),
              (1.5, 2.0, -1.0, -1.0), (0.0, 0.0, 1.0, 0.75)]
    sum_cells = [finest, finest + 1, cells_per_section + finest, 2 * cells_per_section + finest,
                 3 * cells_per_section + finest, 3 * cells_per_section + finest + 1]
    sums = [(40, 120, 0.25, 0.1), (64, 64, 1.0, 3.0), (48, 96, 0.5, 0.4), (24, 12, 0.2, 0.0), (48, 20, 0.3, 0.2),
            (32, 0, 0.0, 0.0)]
    fixed = lambda x: int(x * (1 << 40))
    ears = {"epoch": 2, "probed": True, "lo": [-1.0, -1.0, -1.0], "hi": [1.0, 1.0, 1.0], "scale": 3.0,
            "has_factors": True, "rays_at_start": 1000, "samples_at_start": 24, "paths_at_start": 30,
            "resting": False, "variance_at_start": 0.3,
            "factor_cells": len(factor_cells), "factor_values": 4, "sum_cells": len(sum_cells)}
    base = checkpoint(4, 3, 8, 4, extra={"ears": ears})
    body = base[:-8]
    body += struct.pack("<%dI" % len(factor_cells), *factor_cells)
    body += b"".join(struct.pack("<4f", *v) for v in values)
    body += struct.pack("<%dI" % len(sum_cells), *sum_cells)
    body += b"".join(struct.pack("<6Q", n, rays, fixed(n * v), 0, fixed(n * sq), 0) for n, rays, v, sq in sums)
    # The checksum over every section as the writer hashes them: magic, header line, then each section.
    magic_end = len(b"symphong checkpoint 1\n")
    header_end = body.index(b"\n", magic_end) + 1
    pixels, tiles = 12, 1
    sizes = [tiles * 4, pixels * 24, pixels * 24, pixels * 8, len(factor_cells) * 4, len(factor_cells) * 16,
             len(sum_cells) * 4, len(sum_cells) * 48]
    hsh = CkHash()
    hsh.add(body[:magic_end])
    hsh.add(body[magic_end:header_end])
    at = header_end
    for n in sizes:
        hsh.add(body[at:at + n])
        at += n
    assert at == len(body)
    return body + struct.pack("<Q", hsh.value())


put("fuzz_checkpoint", "ears-4x3-small-fixed.ckpt", b"\x01" + ears_checkpoint())
put("fuzz_checkpoint", "ears-4x3-small-as-written.ckpt", b"\x00" + ears_checkpoint())

# ---- fuzz_settings: the value of a JSON scene's "render" key ---------------------------------------
put("fuzz_settings", "empty.json", "{}")
put("fuzz_settings", "basic.json", '{"spp": 16, "width": 64, "height": 48, "estimator": "cosine", "sampler": "independent", '
    '"max_depth": 4, "seed": 7, "threads": 1, "exposure": 1.5}')
put("fuzz_settings", "symmetric.json", '{"estimator": "symmetric-mix", "symmetric_mode": "spread", "symmetric_orbit": 2, '
    '"symmetric_n": 3, "split": 2, "first_bounce_stream": 3, "joint_first_bounce": true, "no_nee": true, "bump_shadowing": true}')
put("fuzz_settings", "progressive.json", '{"time": 2.5, "target_error": 0.01, "target_region": [0, 0, 8, 8, 4, 4, 2, 2], '
    '"pass_spp": 4, "spp": 1024, "width": 32, "height": 32}')
put("fuzz_settings", "paper.json", '{"estimator": "paper", "paper_refined": true, "exr_half": true}')
put("fuzz_settings", "out-of-range.json", '{"spp": 0, "width": 100000}')

# ---- fuzz_gltf_ext: the "materials" of fuzz_gltf_ext's fixed glTF ---------------------------------------
put("fuzz_gltf_ext", "plain.json", '[{"name": "m", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.6, 0.4, 1], '
    '"metallicFactor": 0.25, "roughnessFactor": 0.5}}]')
put("fuzz_gltf_ext", "transform.json", '[{"name": "t", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "extensions": '
    '{"KHR_texture_transform": {"offset": [0.25, 0.5], "rotation": 0.785, "scale": [2, 3], "texCoord": 0}}}, '
    '"metallicRoughnessTexture": {"index": 1, "extensions": {"KHR_texture_transform": {"scale": [0.5, 0.5]}}}}, '
    '"normalTexture": {"index": 1, "scale": 0.5, "extensions": {"KHR_texture_transform": {"offset": [1, 0]}}}, '
    '"emissiveTexture": {"index": 0, "texCoord": 1}, "emissiveFactor": [1, 1, 1], "alphaMode": "MASK"}]')
put("fuzz_gltf_ext", "specular-ior.json", '[{"name": "s", "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1], '
    '"metallicFactor": 0, "roughnessFactor": 0.2}, "extensions": {"KHR_materials_ior": {"ior": 1.45}, '
    '"KHR_materials_specular": {"specularFactor": 0.5, "specularColorFactor": [1, 0.5, 0.25]}}}]')
put("fuzz_gltf_ext", "emissive-strength.json", '[{"name": "e", "emissiveFactor": [1, 0.5, 0.25], "extensions": '
    '{"KHR_materials_emissive_strength": {"emissiveStrength": 5}}, "alphaMode": "BLEND", '
    '"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]')
put("fuzz_gltf_ext", "two-materials.json", '[{"name": "a", "extensions": {"KHR_materials_specular": {"specularColorFactor": [0, 0, 0]}}}, '
    '{"name": "b", "doubleSided": true}]')

print("seeds in", OUT)
