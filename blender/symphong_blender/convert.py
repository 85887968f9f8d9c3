"""Blender's evaluated scene as the arrays of symphong.Scene.from_arrays: no file in between.

Meshes come from the evaluated depsgraph (modifiers applied, instances expanded), triangulated by Blender's
loop triangles, placed by each instance's world matrix and turned from Blender's Z-up into symphong's
Y-up coordinates (x, y, z) -> (x, z, -y), as Blender's glTF exporter does; the environment map then needs
no other conversion than its rotation. Materials are handed over as Blender's Principled numbers
(base_color, metallic, specular, roughness): the module maps them with the glTF/FBX readers' own C++
function. What cannot be mapped is collected in `Conversion.reports` for Blender's report area.

Runs inside Blender (bpy) and needs NumPy (Debian's blender uses the system python3 and its NumPy).
"""

import math

import numpy as np

# Blender (Z up) -> symphong / glTF (Y up): (x, y, z) -> (x, z, -y). A rotation: windings are kept.
Z_UP_TO_Y_UP = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]])

# Cycles' conventions for a light's power P (watts), as Cycles 3.4 renders them (tests/blender: each light alone
# against Cycles agrees within 0.1%): a point or spot light has radiant intensity P / (4 pi) (W/sr), an area light
# of area A radiance P / (4 A) from its front (-Z) side (not P / (pi A): Cycles' "power" of an area light is
# pi / 4 of what it emits), a sun irradiance = strength. Cycles 3.4 also dims a spot by the cosine to its axis,
# which symphong's spot light does not have: reported.
FOUR_PI = 4.0 * math.pi


def y_up(v):
    """Points or directions (N, 3) (or one (3,)) from Blender's frame to symphong's."""
    return np.asarray(v, dtype=np.float64) @ Z_UP_TO_Y_UP.T


def _triangles(mesh):
    """(T, 3) loop indices of the mesh's triangles and (T,) the polygon of each. Triangles and quads are split as
    Blender's own tessellation splits them (a quad along its 0-2 diagonal), with NumPy; a mesh with larger
    polygons takes Blender's loop triangles (its polygon fill)."""
    polys = len(mesh.polygons)
    total = np.empty(polys, np.int32)
    mesh.polygons.foreach_get("loop_total", total)
    if polys and total.max() > 4:
        mesh.calc_loop_triangles()
        n = len(mesh.loop_triangles)
        tri_loops = np.empty(n * 3, np.int32)
        mesh.loop_triangles.foreach_get("loops", tri_loops)
        tri_poly = np.empty(n, np.int32)
        mesh.loop_triangles.foreach_get("polygon_index", tri_poly)
        return tri_loops.reshape(-1, 3), tri_poly
    start = np.empty(polys, np.int32)
    mesh.polygons.foreach_get("loop_start", start)
    keep = total >= 3
    first = np.stack([start, start + 1, start + 2], axis=1)[keep]
    quads = total == 4
    second = np.stack([start, start + 2, start + 3], axis=1)[quads]
    poly = np.arange(polys, dtype=np.int32)
    return np.concatenate([first, second]), np.concatenate([poly[keep], poly[quads]])


def _normals(mesh, tri_loops, tri_verts, tri_poly):
    """Shading normals and their (T, 3) index per corner, or (None, None) for a mesh without smooth faces (the
    triangles' own normals are then exact). Smooth faces take Blender's vertex normals, flat ones their face's
    normal; custom normals and auto smooth (split at sharp edges) take Blender's per-corner normals."""
    smooth = np.empty(len(mesh.polygons), bool)
    mesh.polygons.foreach_get("use_smooth", smooth)
    if not smooth.any() and not mesh.has_custom_normals:
        return None, None
    if mesh.has_custom_normals or mesh.use_auto_smooth:
        mesh.calc_normals_split()
        n = np.empty(len(mesh.loops) * 3, np.float32)
        mesh.loops.foreach_get("normal", n)
        return n.reshape(-1, 3), tri_loops
    vn = np.empty(len(mesh.vertices) * 3, np.float32)
    mesh.vertex_normals.foreach_get("vector", vn)
    if smooth.all():
        return vn.reshape(-1, 3), tri_verts
    pn = np.empty(len(mesh.polygons) * 3, np.float32)
    mesh.polygon_normals.foreach_get("vector", pn)
    flat = ~smooth[tri_poly]
    idx = tri_verts.astype(np.int64)
    idx[flat] = len(mesh.vertices) + tri_poly[flat, None]
    return np.concatenate([vn.reshape(-1, 3), pn.reshape(-1, 3)]), idx


class Conversion:
    """The keyword arguments of symphong.Scene.from_arrays for one evaluated depsgraph, and the reports."""

    def __init__(self, depsgraph, width, height):
        self.depsgraph = depsgraph
        self.scene = depsgraph.scene
        self.width, self.height = width, height
        self.reports = []  # (level, message): shown in Blender's report area; the render goes on
        self._reported = set()
        self.materials = []  # dicts for from_arrays
        self._material_index = {}  # bpy material name (or None) -> index in self.materials
        self._images = {}  # (image name, srgb, channels) -> array
        self._mesh_cache = {}  # (object name, data name) -> arrays in object space
        self.positions, self.triangles, self.material_ids = [], [], []
        self.normals, self.uvs, self.tangents = [], [], []
        self.vertex_count = 0
        self.corner_count = 0
        self.lights = []
        self.environment = None
        self.camera = None

    # ------------------------------------------------------------------------------------------ reports
    def report(self, message, level="WARNING"):
        if message not in self._reported:
            self._reported.add(message)
            self.reports.append((level, message))

    # ------------------------------------------------------------------------------------------ images
    def image_array(self, image, srgb, channels):
        """An image's pixels, row 0 at the top: uint8 for 8-bit images (sRGB-encoded or not, as Blender
        stores them; the module decodes them as it decodes a PNG), float32 linear for float images."""
        key = (image.name, srgb, channels)
        if key in self._images:
            return self._images[key]
        w, h = image.size
        if w == 0 or h == 0:
            self.report(f"image '{image.name}' has no pixels (missing file?); its texture is left out")
            self._images[key] = None
            return None
        flat = np.empty(w * h * image.channels, dtype=np.float32)
        image.pixels.foreach_get(flat)
        pixels = flat.reshape(h, w, image.channels)[::-1]  # Blender stores the bottom row first
        if image.channels < channels:  # a grey image: repeat its first channel, alpha 1
            rgb = np.repeat(pixels[:, :, :1], 3, axis=2)
            alpha = pixels[:, :, 1:2] if image.channels == 2 else np.ones((h, w, 1), np.float32)
            pixels = np.concatenate([rgb, alpha], axis=2)
        pixels = np.ascontiguousarray(pixels[:, :, :channels])
        if image.is_float:
            value = {"image": pixels.astype(np.float32), "srgb": False}
        else:
            value = {"image": np.rint(np.clip(pixels, 0, 1) * 255).astype(np.uint8), "srgb": srgb}
        self._images[key] = value
        return value

    def texture(self, node, where, srgb_default, channels=3):
        """A texture dict from an Image Texture node, or None with a report."""
        if node.image is None:
            self.report(f"{where}: Image Texture node '{node.name}' has no image; left out")
            return None
        if node.inputs["Vector"].is_linked:
            self.report(f"{where}: the texture coordinates of '{node.name}' come from other nodes; the UV map is used as it is")
        if node.projection != "FLAT":
            self.report(f"{where}: '{node.name}' projection {node.projection} is not mapped; UV mapping used")
        srgb = node.image.colorspace_settings.name == "sRGB" if not node.image.is_float else False
        value = self.image_array(node.image, srgb if srgb_default is None else srgb_default and srgb, channels)
        if value is None:
            return None
        value = dict(value)
        if node.extension == "EXTEND":
            value["wrap"] = "clamp"
        elif node.extension != "REPEAT":
            self.report(f"{where}: '{node.name}' extension {node.extension} is not mapped; repeated")
        return value

    # ------------------------------------------------------------------------------------------ materials
    def material(self, mat):
        """Index of a Blender material in self.materials (None: Blender's default grey)."""
        key = mat.name if mat is not None else None
        if key in self._material_index:
            return self._material_index[key]
        spec = self._map_material(mat)
        self._material_index[key] = len(self.materials)
        self.materials.append(spec)
        return self._material_index[key]

    def _map_material(self, mat):
        if mat is None:
            return {"name": "default", "base_color": (0.8, 0.8, 0.8), "metallic": 0.0, "specular": 0.5, "roughness": 0.5}
        name = mat.name
        where = f"material '{name}'"
        if not mat.use_nodes or mat.node_tree is None:
            c = mat.diffuse_color
            return {"name": name, "base_color": (c[0], c[1], c[2]), "metallic": mat.metallic, "specular": mat.specular_intensity,
                    "roughness": mat.roughness}
        out = None
        for node in mat.node_tree.nodes:
            if node.type == "OUTPUT_MATERIAL" and node.is_active_output and node.target in {"ALL", "CYCLES"}:
                out = node
        if out is None:
            self.report(f"{where}: no active Material Output node; rendered as a grey diffuse (0.8)")
            return {"name": name, "rho_d": 0.8}
        if out.inputs["Volume"].is_linked:
            self.report(f"{where}: its volume is not rendered (symphong renders surfaces only)")
        if out.inputs["Displacement"].is_linked:
            self.report(f"{where}: its displacement is not rendered")
        if not out.inputs["Surface"].is_linked:
            return {"name": name, "rho_d": 0.0}  # Cycles renders an unconnected surface black
        node = out.inputs["Surface"].links[0].from_node
        return self._map_surface(node, name, where)

    def _value(self, socket):
        v = socket.default_value
        try:
            return tuple(v)[:3]
        except TypeError:
            return float(v)

    def _linked_image(self, socket, where, what):
        """The Image Texture node feeding a socket directly (None when unlinked); another node is reported."""
        if not socket.is_linked:
            return None
        node = socket.links[0].from_node
        if node.type == "TEX_IMAGE":
            return node
        self.report(f"{where}: {what} comes from a '{node.bl_idname}' node, which is not mapped; its own value is used")
        return None

    def _map_surface(self, node, name, where):
        if node.type == "BSDF_PRINCIPLED":
            i = node.inputs
            spec = {"name": name, "base_color": self._value(i["Base Color"]), "metallic": self._value(i["Metallic"]),
                    "specular": self._value(i["Specular"]), "roughness": self._value(i["Roughness"])}
            tex = self._linked_image(i["Base Color"], where, "Base Color")
            if tex is not None:
                t = self.texture(tex, where, None)
                if t is not None:
                    spec["base_color_texture"] = t
                    spec["base_color"] = (1.0, 1.0, 1.0)
            for socket in ("Metallic", "Specular", "Roughness"):
                if i[socket].is_linked:
                    self.report(f"{where}: a texture on {socket} is not mapped; its value {self._value(i[socket]):g} is used")
            emission = self._value(i["Emission"])
            strength = self._value(i["Emission Strength"]) if "Emission Strength" in i else 1.0
            if max(emission) * strength > 0:
                spec["emission"] = tuple(c * strength for c in emission)
            tex = self._linked_image(i["Emission"], where, "Emission")
            if tex is not None:
                t = self.texture(tex, where, None)
                if t is not None:
                    spec["emission_texture"] = t
                    spec["emission"] = (strength, strength, strength)
            for socket, idle in (("Subsurface", 0.0), ("Transmission", 0.0), ("Clearcoat", 0.0), ("Sheen", 0.0)):
                if socket in i and (i[socket].is_linked or self._value(i[socket]) != idle):
                    self.report(f"{where}: Principled {socket} is not mapped (symphong's surfaces are Phong); left out")
            if i["Alpha"].is_linked:
                tex = self._linked_image(i["Alpha"], where, "Alpha")
                if tex is not None:
                    t = self.texture(tex, where, False, channels=4)
                    if t is not None:
                        spec["alpha_texture"] = t
            elif self._value(i["Alpha"]) < 1.0:
                self.report(f"{where}: Alpha {self._value(i['Alpha']):g} (partial transparency) is not mapped; opaque")
            self._normal_input(i["Normal"], spec, where)
            return spec
        if node.type == "BSDF_DIFFUSE":
            spec = {"name": name, "rho_d": self._value(node.inputs["Color"]), "rho_s": 0.0}
            tex = self._linked_image(node.inputs["Color"], where, "Color")
            if tex is not None:
                t = self.texture(tex, where, None)
                if t is not None:
                    spec["diffuse_texture"], spec["rho_d"] = t, 1.0
            if self._value(node.inputs["Roughness"]) != 0:
                self.report(f"{where}: Diffuse BSDF roughness (Oren-Nayar) is not mapped; Lambertian")
            self._normal_input(node.inputs["Normal"], spec, where)
            return spec
        if node.type == "EMISSION":
            c, s = self._value(node.inputs["Color"]), self._value(node.inputs["Strength"])
            return {"name": name, "rho_d": 0.0, "emission": tuple(x * s for x in c)}
        if node.type == "BSDF_GLOSSY":
            # A metal of this colour: the Principled mapping with metallic 1.
            return {"name": name, "base_color": self._value(node.inputs["Color"]), "metallic": 1.0, "specular": 0.5,
                    "roughness": self._value(node.inputs["Roughness"])}
        self.report(f"{where}: surface node '{node.name}' ({node.bl_idname}) is not mapped; rendered as a grey diffuse (0.8)")
        return {"name": name, "rho_d": 0.8}

    def _normal_input(self, socket, spec, where):
        if not socket.is_linked:
            return
        node = socket.links[0].from_node
        if node.type == "NORMAL_MAP":
            if node.space != "TANGENT":
                self.report(f"{where}: Normal Map space {node.space} is not mapped (tangent space only); left out")
                return
            tex = self._linked_image(node.inputs["Color"], where, "the Normal Map's Color")
            if tex is None:
                return
            t = self.texture(tex, where, False)
            if t is None:
                return
            spec["normal_texture"] = t
            spec["normal_scale"] = self._value(node.inputs["Strength"])
            spec["_tangents"] = True
            return
        if node.type == "BUMP":
            self.report(f"{where}: Bump node is not mapped; left out")
            return
        self.report(f"{where}: Normal input from '{node.bl_idname}' is not mapped; left out")

    # ------------------------------------------------------------------------------------------ meshes
    def _mesh_arrays(self, obj):
        """Object-space arrays of an evaluated object's mesh, cached for its instances."""
        key = (obj.name, obj.data.name if obj.data is not None else "")
        if key in self._mesh_cache:
            return self._mesh_cache[key]
        mesh = obj.to_mesh()
        if mesh is None:
            self._mesh_cache[key] = None
            return None
        try:
            tri_loops, tri_poly = _triangles(mesh)
            if len(tri_loops) == 0:
                self._mesh_cache[key] = None
                return None
            loops = len(mesh.loops)
            loop_vert = np.empty(loops, np.int32)
            mesh.loops.foreach_get("vertex_index", loop_vert)
            tri_verts = loop_vert[tri_loops]
            verts = np.empty(len(mesh.vertices) * 3, np.float32)
            mesh.vertices.foreach_get("co", verts)
            mats = [self.material(s.material) for s in obj.material_slots] or [self.material(None)]
            if len(mats) > 1:
                slots = np.empty(len(mesh.polygons), np.int32)
                mesh.polygons.foreach_get("material_index", slots)
                mat_ids = np.asarray(mats, np.int64)[np.clip(slots, 0, len(mats) - 1)][tri_poly]
            else:
                mat_ids = np.full(len(tri_loops), mats[0], np.int64)
            normals, normal_idx = _normals(mesh, tri_loops, tri_verts, tri_poly)
            uvs = None
            uv_layer = mesh.uv_layers.active
            for layer in mesh.uv_layers:
                if layer.active_render:
                    uv_layer = layer
            if uv_layer is not None:
                uvs = np.empty(loops * 2, np.float32)
                uv_layer.data.foreach_get("uv", uvs)
                uvs = uvs.reshape(-1, 2)
            tangents = None
            if uvs is not None and any(self.materials[m].get("_tangents") for m in set(mats)):
                mesh.calc_tangents(uvmap=uv_layer.name)  # MikkTSpace, as Cycles' normal maps use
                t = np.empty(loops * 3, np.float32)
                mesh.loops.foreach_get("tangent", t)
                sign = np.empty(loops, np.float32)
                mesh.loops.foreach_get("bitangent_sign", sign)
                tangents = (t.reshape(-1, 3), sign)
            arrays = dict(positions=verts.reshape(-1, 3), triangles=tri_verts, loops=tri_loops, material_ids=mat_ids, normals=normals,
                          normal_indices=normal_idx, uvs=uvs, tangents=tangents, loop_count=loops)
        finally:
            obj.to_mesh_clear()
        self._mesh_cache[key] = arrays
        return arrays

    def add_mesh(self, obj, matrix):
        arrays = self._mesh_arrays(obj)
        if arrays is None:
            return
        m = np.array(matrix, dtype=np.float64)
        linear, offset = m[:3, :3], m[:3, 3]
        to_y = Z_UP_TO_Y_UP @ linear
        self.positions.append(arrays["positions"] @ to_y.T + Z_UP_TO_Y_UP @ offset)
        triangles = arrays["triangles"].astype(np.int64) + self.vertex_count
        loops = arrays["loops"].astype(np.int64) + self.corner_count
        if np.linalg.det(linear) < 0:  # a mirrored instance: keep the front faces in front
            triangles = triangles[:, [0, 2, 1]]
            loops = loops[:, [0, 2, 1]]
        self.triangles.append(triangles)
        self.material_ids.append(arrays["material_ids"])
        count = arrays["loop_count"]
        if arrays["normals"] is None:
            self.normals.append(None)
        else:
            idx = arrays["normal_indices"]
            if np.linalg.det(linear) < 0:
                idx = idx[:, [0, 2, 1]]
            self.normals.append((arrays["normals"] @ (Z_UP_TO_Y_UP @ np.linalg.inv(linear).T).T, idx))
        self.uvs.append(arrays["uvs"])
        if arrays["tangents"] is not None:
            t, sign = arrays["tangents"]
            # The bitangent's sign is relative to cross(n, t): a mirrored transform flips it.
            flip = -1.0 if np.linalg.det(linear) < 0 else 1.0
            self.tangents.append(np.concatenate([t @ to_y.T, (sign * flip)[:, None]], axis=1))
        else:
            self.tangents.append(None)
        self._loops.append((loops, count))
        self.vertex_count += len(arrays["positions"])
        self.corner_count += count

    # ------------------------------------------------------------------------------------------ lights
    def add_light(self, obj, matrix):
        light = obj.data
        m = np.array(matrix, dtype=np.float64)
        position = y_up(m[:3, 3])
        axis = -m[:3, 2]  # lights shine along their local -Z
        direction = y_up(axis / np.linalg.norm(axis))
        colour = np.array(light.color[:3], dtype=np.float64)
        where = f"light '{obj.name}'"
        if light.type in {"POINT", "SPOT"}:
            if light.shadow_soft_size > 0:
                self.report(f"{where}: radius {light.shadow_soft_size:g} is rendered as a point (hard shadows)", "INFO")
            intensity = colour * light.energy / FOUR_PI
            if light.type == "POINT":
                self.lights.append({"type": "point", "position": position, "intensity": intensity})
            else:
                half = math.degrees(light.spot_size) / 2
                if half > 90:
                    self.report(f"{where}: spot size {2 * half:g} degrees is wider than symphong's 180; cut to 180")
                    half = 90.0
                cos_outer = math.cos(math.radians(half))
                cos_inner = cos_outer + (1 - cos_outer) * light.spot_blend  # Cycles' smoothstep between them
                inner = math.degrees(math.acos(min(1.0, cos_inner)))
                inner = min(inner, half * (1 - 1e-6))
                self.lights.append({"type": "spot", "position": position, "direction": direction, "intensity": intensity,
                                    "angle": half, "inner": inner})
                self.report(f"{where}: Cycles dims a spot light by the cosine to its axis as well; symphong's spot does not "
                            f"(up to {100 * (1 / cos_outer - 1):.0f}% brighter at the cone's edge)")
        elif light.type == "SUN":
            if light.angle > 0:
                self.report(f"{where}: sun angle {math.degrees(light.angle):g} degrees is rendered as parallel light", "INFO")
            self.lights.append({"type": "directional", "direction": direction, "irradiance": colour * light.energy})
        elif light.type == "AREA":
            x, y = m[:3, 0], m[:3, 1]
            sx = light.size
            sy = light.size_y if light.shape in {"RECTANGLE", "ELLIPSE"} else light.size
            if light.shape in {"DISK", "ELLIPSE"}:
                self.report(f"{where}: {light.shape.lower()} area light rendered as a rectangle of the same area")
                sx, sy = sx * math.sqrt(math.pi) / 2, sy * math.sqrt(math.pi) / 2
            if getattr(light, "spread", math.pi) < math.pi - 1e-6:
                self.report(f"{where}: area light spread {math.degrees(light.spread):g} degrees is not mapped (180)")
            edge1, edge2 = y_up(sy * y), y_up(sx * x)  # cross(edge1, edge2) is the light's -Z: its front
            corner = position - edge1 / 2 - edge2 / 2
            area = np.linalg.norm(np.cross(edge1, edge2))
            self.lights.append({"type": "quad", "corner": corner, "edge1": edge1, "edge2": edge2,
                                "radiance": colour * light.energy / (4.0 * area)})
            self.report(f"{where}: symphong's area light is an emissive quad, a surface: the camera sees it and it casts shadows "
                        "(Cycles' area light does neither)", "INFO")
        else:
            self.report(f"{where}: light type {light.type} is not mapped; left out")

    # ------------------------------------------------------------------------------------------ world
    def add_world(self, world):
        if world is None:
            self.environment = 0.0
            return
        if not world.use_nodes or world.node_tree is None:
            self.environment = tuple(world.color[:3])
            return
        out = None
        for node in world.node_tree.nodes:
            if node.type == "OUTPUT_WORLD" and node.is_active_output and node.target in {"ALL", "CYCLES"}:
                out = node
        if out is None or not out.inputs["Surface"].is_linked:
            self.environment = 0.0
            return
        if out.inputs["Volume"].is_linked:
            self.report("world: its volume is not rendered")
        bg = out.inputs["Surface"].links[0].from_node
        if bg.type != "BACKGROUND":
            self.report(f"world: surface node '{bg.bl_idname}' is not mapped; black")
            self.environment = 0.0
            return
        strength = self._value(bg.inputs["Strength"])
        col = bg.inputs["Color"]
        if not col.is_linked:
            self.environment = tuple(c * strength for c in self._value(col))
            return
        tex = col.links[0].from_node
        if tex.type != "TEX_ENVIRONMENT" or tex.image is None:
            self.report(f"world: colour from '{tex.bl_idname}' is not mapped; its Background colour is used")
            self.environment = tuple(c * strength for c in self._value(col))
            return
        if tex.projection != "EQUIRECTANGULAR":
            self.report(f"world: environment projection {tex.projection} is not mapped; taken as equirectangular")
        rotation = 0.0
        if tex.inputs["Vector"].is_linked:
            mapping = tex.inputs["Vector"].links[0].from_node
            if mapping.type == "MAPPING" and mapping.vector_type in {"POINT", "TEXTURE"}:
                r = mapping.inputs["Rotation"].default_value
                if abs(r[0]) > 1e-9 or abs(r[1]) > 1e-9 or any(abs(s - 1) > 1e-9 for s in mapping.inputs["Scale"].default_value):
                    self.report("world: the environment's Mapping node is mapped by its Z rotation only")
                rotation = math.degrees(r[2]) * (-1 if mapping.vector_type == "TEXTURE" else 1)
            else:
                self.report(f"world: environment coordinates from '{mapping.bl_idname}' are not mapped")
        pixels = self.image_array(tex.image, False, 3)
        if pixels is None:
            self.environment = 0.0
            return
        image = pixels["image"]
        if image.dtype == np.uint8:  # an 8-bit environment: decode as a colour map would be decoded
            image = _srgb_to_linear(image) if tex.image.colorspace_settings.name == "sRGB" else image.astype(np.float32) / 255
        # Blender's equirectangular u = 0.5 - atan2(d.y, d.x) / 2 pi is symphong's u = 0.5 + atan2(d.x, -d.z) / 2 pi
        # - rotation / 360 in its Y-up frame (d.x, d.z, -d.y) at rotation 90; a Mapping node that turns the lookup
        # vector by g about Z adds g.
        self.environment = {"image": image, "scale": strength, "rotation": 90.0 + rotation}

    # ------------------------------------------------------------------------------------------ camera
    def add_camera(self, cam_obj):
        if cam_obj is None:
            self.report("the scene has no active camera; symphong frames it automatically")
            return
        cam = cam_obj.data
        r = self.scene.render
        m = np.array(cam_obj.matrix_world, dtype=np.float64)
        if cam.type != "PERSP":
            self.report(f"camera '{cam_obj.name}': type {cam.type} is not mapped; perspective")
        if cam.shift_x != 0 or cam.shift_y != 0:
            self.report(f"camera '{cam_obj.name}': lens shift is not mapped")
        if r.pixel_aspect_x != r.pixel_aspect_y:
            self.report("non-square pixels (pixel aspect) are not mapped")
        if cam.dof.use_dof:
            self.report(f"camera '{cam_obj.name}': depth of field is not mapped (pinhole)")
        if r.use_border:
            self.report("render region (border) is not mapped: the whole frame is rendered")
        aspect = self.width / self.height
        fit = cam.sensor_fit
        if fit == "AUTO":
            fit = "HORIZONTAL" if self.width >= self.height else "VERTICAL"
            sensor = cam.sensor_width
        else:
            sensor = cam.sensor_width if fit == "HORIZONTAL" else cam.sensor_height
        half = math.atan(sensor / (2 * cam.lens))  # along the fitted side
        if fit == "HORIZONTAL":
            half = math.atan(math.tan(half) / aspect)
        fov_y = math.degrees(2 * half)
        position = m[:3, 3]
        forward = -m[:3, 2] / np.linalg.norm(m[:3, 2])
        up = m[:3, 1] / np.linalg.norm(m[:3, 1])
        self.camera = {"position": y_up(position), "target": y_up(position + forward), "up": y_up(up), "fov": fov_y}

    # ------------------------------------------------------------------------------------------ all
    def run(self):
        self._loops = []
        for inst in self.depsgraph.object_instances:
            obj = inst.object
            if obj.type == "LIGHT":
                self.add_light(obj, inst.matrix_world)
            elif obj.type in {"MESH", "CURVE", "SURFACE", "META", "FONT"}:
                if obj.type == "MESH":
                    for ps in obj.particle_systems:
                        if ps.settings.type == "HAIR":
                            self.report(f"object '{obj.name}': hair system '{ps.name}' is not rendered")
                self.add_mesh(obj, inst.matrix_world)
            elif obj.type == "CURVES":
                self.report(f"object '{obj.name}': hair curves are not rendered")
            elif obj.type == "VOLUME":
                self.report(f"object '{obj.name}': volumes are not rendered")
            elif obj.type in {"POINTCLOUD", "GPENCIL"}:
                self.report(f"object '{obj.name}': {obj.type.lower()} objects are not rendered")
        self.add_world(self.scene.world)
        self.add_camera(self.scene.camera)
        return self.arguments()

    def arguments(self):
        """The keyword arguments of symphong.Scene.from_arrays."""
        if not self.triangles:
            raise ValueError("the scene has no meshes to render")
        kw = {"positions": np.concatenate(self.positions), "triangles": np.concatenate(self.triangles),
              "material_ids": np.concatenate(self.material_ids), "name": self.scene.name}
        corner_total = self.corner_count
        corner_index = np.concatenate([l for l, _ in self._loops])
        if any(n is not None for n in self.normals):
            # A mesh without smooth faces points at one zero normal: from_arrays uses the triangles' own there.
            rows, index, offset = [], [], 0
            for entry, tris in zip(self.normals, self.triangles):
                if entry is None:
                    rows.append(np.zeros((1, 3), np.float32))
                    index.append(np.full(tris.shape, offset, np.int64))
                    offset += 1
                else:
                    rows.append(entry[0])
                    index.append(entry[1].astype(np.int64) + offset)
                    offset += len(entry[0])
            kw["normals"], kw["normal_indices"] = np.concatenate(rows), np.concatenate(index)
        if any(u is not None for u in self.uvs):
            kw["uvs"] = np.concatenate([u if u is not None else np.zeros((c, 2)) for u, (_, c) in zip(self.uvs, self._loops)])
            kw["uv_indices"] = corner_index
        if any(t is not None for t in self.tangents):
            kw["tangents"] = np.concatenate(
                [t if t is not None else np.tile([1.0, 0, 0, 1], (c, 1)) for t, (_, c) in zip(self.tangents, self._loops)])
            kw["tangent_indices"] = corner_index
        assert corner_index.max(initial=-1) < corner_total
        kw["materials"] = [{k: v for k, v in m.items() if not k.startswith("_")} for m in self.materials]
        kw["lights"] = self.lights
        kw["environment"] = self.environment
        if self.camera is not None:
            kw["camera"] = self.camera
        return kw


def _srgb_to_linear(image):
    c = image.astype(np.float32) / 255
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4).astype(np.float32)


def convert(depsgraph, width, height):
    """(from_arrays keyword arguments, reports) for an evaluated depsgraph rendered at width x height."""
    c = Conversion(depsgraph, width, height)
    kwargs = c.run()
    return kwargs, c.reports
