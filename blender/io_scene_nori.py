# Blender add-on: File > Export > Nori scene (.xml). Writes the scene as a nori XML file,
# its meshes as OBJ files under meshes/ and its image textures under textures/, beside
# the XML. What it cannot map (a shader node, a light setting, an object type) is listed
# in warnings that name the object; nothing is dropped silently. The command line is
# blender/export.py; the mapping is described in the README ("Blender exporter").
#
# Axes: Blender is z-up, nori y-up. Every world transform is premultiplied by
# Z_UP_TO_Y_UP, the rotation of -90 degrees about x, (x, y, z) -> (x, z, -y).
# Light units were measured against Cycles 3.4 renders of a white plane (see the README):
# point Power P is the flux (I = P/4pi), spot I = P/4pi on its axis, sun Strength the
# irradiance, area radiance P/(4A), emission shaders and the world radiance = strength.
# Volumes (Principled Volume, Volume Scatter, Volume Absorption on a mesh) become the
# mesh's interior homogeneous medium with Cycles' coefficients, inside a null BSDF when
# the material has no surface shader; such scenes are rendered with volpath.

bl_info = {
    "name": "Nori scene exporter",
    "author": "the nori authors",
    "version": (1, 0, 0),
    "blender": (3, 4, 0),
    "location": "File > Export > Nori scene (.xml)",
    "description": "Export the scene for the nori renderer: meshes, materials, lights, "
                   "camera, world",
    "category": "Import-Export",
}

import math
import os
import shutil
import xml.etree.ElementTree as ET

import bpy
from mathutils import Matrix, Vector

Z_UP_TO_Y_UP = Matrix(((1, 0, 0, 0), (0, 0, 1, 0), (0, -1, 0, 0), (0, 0, 0, 1)))
# Blender cameras look along local -z with +x to the image's right; nori's (the "epfl"
# convention, written explicitly) along +z with +x to the image's left: a half turn
# about y maps one onto the other.
CAMERA_FRAME = Matrix(((-1, 0, 0, 0), (0, 1, 0, 0), (0, 0, -1, 0), (0, 0, 0, 1)))
# Blender lights shine along local -z, nori's spot along +z: a half turn about x.
LIGHT_FRAME = Matrix(((1, 0, 0, 0), (0, -1, 0, 0), (0, 0, -1, 0), (0, 0, 0, 1)))
# Blender's equirectangular world maps u = (pi - atan2(y, x)) / 2pi, v = polar angle from
# +z; nori's envmap (Mitsuba 3's) u = phi / 2pi about +y with (sin phi, 0, -cos phi) at
# the equator. After Z_UP_TO_Y_UP the two differ by a quarter turn about y.
ENVMAP_FRAME = Matrix(((0, 0, 1, 0), (0, 1, 0, 0), (-1, 0, 0, 0), (0, 0, 0, 1)))

# Principled BSDF inputs under their Blender 3.x names, with their 4.x names.
PRINCIPLED_ALIASES = {
    "Subsurface": "Subsurface Weight",
    "Specular": "Specular IOR Level",
    "Sheen": "Sheen Weight",
    "Clearcoat": "Coat Weight",
    "Clearcoat Roughness": "Coat Roughness",
    "Transmission": "Transmission Weight",
    "Emission": "Emission Color",
}


def format_numbers(values):
    return ", ".join(f"{v:.7g}" for v in values)


def matrix_value(matrix):
    return " ".join(f"{matrix[r][c]:.7g}" for r in range(4) for c in range(4))


def slug(name):
    """A file-name-safe version of a Blender name."""
    return "".join(c if c.isalnum() or c in "-_" else "_" for c in name) or "unnamed"


class Exporter:
    """Writes one scene; `warnings` lists what could not be mapped."""

    def __init__(self, context, filepath, samples=64, integrator=None, max_depth=-1):
        self.context = context
        self.scene = context.scene
        self.depsgraph = context.evaluated_depsgraph_get()
        self.filepath = os.path.abspath(filepath)
        self.folder = os.path.dirname(self.filepath)
        self.samples = samples
        self.integrator = integrator  # None: path_mis, or volpath if there are volumes
        self.has_media = False
        self.max_depth = max_depth
        self.warnings = []
        self.meshes = {}    # (mesh key, material index) -> OBJ path relative to the scene
        # (mesh key, materials) -> [(files, materials, nori toWorld value, owner)]: every
        # placement of a geometry, written once all are known (export_placements)
        self.placements = {}
        self.textures = {}  # image name -> path relative to the scene
        self.root = ET.Element("scene")

    def warn(self, owner, message):
        text = f"{owner}: {message}"
        if text not in self.warnings:
            self.warnings.append(text)

    # --- the scene -------------------------------------------------------------------

    def export(self):
        integrator = ET.SubElement(self.root, "integrator", type=self.integrator or "path_mis")
        if self.max_depth >= 0:
            ET.SubElement(integrator, "integer", name="maxDepth", value=str(self.max_depth))
        sampler = ET.SubElement(self.root, "sampler", type="independent")
        ET.SubElement(sampler, "integer", name="sampleCount", value=str(self.samples))
        self.export_camera()
        self.export_world()
        for instance in self.depsgraph.object_instances:
            self.export_instance(instance)
        self.export_placements()
        if self.has_media:
            if self.integrator is None:
                integrator.set("type", "volpath")
            elif self.integrator != "volpath":
                self.warn("scene", f"has volumes, which integrator '{self.integrator}' "
                                   "ignores (volpath renders them)")
        ET.indent(self.root, space="    ")
        header = "<?xml version=\"1.0\"?>\n<!-- Exported from Blender by blender/io_scene_nori.py -->\n"
        with open(self.filepath, "w", encoding="utf-8") as file:
            file.write(header + ET.tostring(self.root, encoding="unicode") + "\n")
        return self.warnings

    def export_instance(self, instance):
        obj = instance.object
        original = obj.original
        if original.hide_render:
            return
        owner = f"object '{original.name}'"
        kind = obj.type
        if kind in ("MESH", "CURVE", "SURFACE", "META", "FONT"):
            self.export_mesh(obj, instance.matrix_world.copy(), owner)
        elif kind == "LIGHT":
            self.export_light(obj, instance.matrix_world.copy(), owner)
        elif kind == "CAMERA":
            if original != self.scene.camera:
                self.warn(owner, "only the scene's camera is exported")
        elif kind == "EMPTY":
            pass  # no geometry; its instances arrive as instances of their own
        else:
            self.warn(owner, f"object type {kind} is not supported: not exported")

    # --- camera ------------------------------------------------------------------------

    def export_camera(self):
        camera_object = self.scene.camera
        render = self.scene.render
        width = int(render.resolution_x * render.resolution_percentage / 100)
        height = int(render.resolution_y * render.resolution_percentage / 100)
        element = ET.SubElement(self.root, "camera", type="perspective")
        ET.SubElement(element, "integer", name="width", value=str(width))
        ET.SubElement(element, "integer", name="height", value=str(height))
        ET.SubElement(element, "string", name="convention", value="epfl")
        if camera_object is None:
            self.warn("scene", "has no camera: a default one is written")
            return
        owner = f"camera '{camera_object.name}'"
        camera = camera_object.data
        if camera.type != "PERSP":
            self.warn(owner, f"type {camera.type} is not supported: exported as perspective")
        if camera.shift_x != 0 or camera.shift_y != 0:
            self.warn(owner, "lens shift is not supported: ignored")
        if render.pixel_aspect_x != render.pixel_aspect_y:
            self.warn(owner, "non-square pixels are not supported: ignored")
        ET.SubElement(element, "float", name="fov",
                      value=f"{math.degrees(horizontal_fov(camera, width, height)):.7g}")
        ET.SubElement(element, "float", name="nearClip", value=f"{camera.clip_start:.7g}")
        ET.SubElement(element, "float", name="farClip", value=f"{camera.clip_end:.7g}")
        world = camera_object.matrix_world
        location, rotation, _ = world.decompose()
        frame = Matrix.Translation(location) @ rotation.to_matrix().to_4x4()
        transform = ET.SubElement(element, "transform", name="toWorld")
        ET.SubElement(transform, "matrix", value=matrix_value(Z_UP_TO_Y_UP @ frame @ CAMERA_FRAME))
        if camera.dof.use_dof:
            # Thin lens: aperture radius = focal length / (2 f-number), in scene units
            # (Blender's lens is in millimetres, its scene units metres).
            focus = camera.dof.focus_distance
            if camera.dof.focus_object is not None:
                to_focus = camera.dof.focus_object.matrix_world.translation - location
                focus = -to_focus.dot(rotation.to_matrix().col[2])
            radius = camera.lens / 1000.0 / (2.0 * camera.dof.aperture_fstop)
            ET.SubElement(element, "float", name="apertureRadius", value=f"{radius:.7g}")
            ET.SubElement(element, "float", name="focalDistance", value=f"{focus:.7g}")
            if camera.dof.aperture_blades != 0:
                self.warn(owner, "polygonal aperture blades are not supported: a round lens")

    # --- world -------------------------------------------------------------------------

    def export_world(self):
        world = self.scene.world
        if world is None:
            return
        owner = f"world '{world.name}'"
        if not world.use_nodes:
            self.constant_environment(world.color, 1.0)
            return
        output = world.node_tree.get_output_node("CYCLES")
        if output and output.inputs["Volume"].is_linked:
            self.warn(owner, "a world volume is not supported: ignored")
        links = output.inputs["Surface"].links if output else []
        if not links:
            return
        node = links[0].from_node
        if node.type != "BACKGROUND":
            self.warn(owner, f"node '{node.name}' ({node.type}) is not supported: no environment")
            return
        strength = node.inputs["Strength"].default_value
        if node.inputs["Strength"].is_linked:
            self.warn(owner, "a linked Strength is not supported: its default value is used")
        color_input = node.inputs["Color"]
        if not color_input.is_linked:
            self.constant_environment(color_input.default_value, strength)
            return
        source = color_input.links[0].from_node
        if source.type != "TEX_ENVIRONMENT" or source.image is None:
            self.warn(owner, f"node '{source.name}' ({source.type}) is not supported: the "
                             "background colour is used")
            self.constant_environment(color_input.default_value, strength)
            return
        if source.inputs["Vector"].is_linked:
            self.warn(owner, "a mapped environment texture is not supported: mapping ignored")
        if source.projection != "EQUIRECTANGULAR":
            self.warn(owner, f"{source.projection} projection is not supported: read as "
                             "equirectangular")
        emitter = ET.SubElement(self.root, "emitter", type="envmap")
        ET.SubElement(emitter, "string", name="filename",
                      value=self.copy_image(source.image, owner))
        ET.SubElement(emitter, "float", name="scale", value=f"{strength:.7g}")
        transform = ET.SubElement(emitter, "transform", name="toWorld")
        ET.SubElement(transform, "matrix", value=matrix_value(ENVMAP_FRAME))

    def constant_environment(self, color, strength):
        radiance = [c * strength for c in color[:3]]
        if max(radiance) > 0:
            emitter = ET.SubElement(self.root, "emitter", type="constant")
            ET.SubElement(emitter, "color", name="radiance", value=format_numbers(radiance))

    # --- lights ------------------------------------------------------------------------

    def export_light(self, obj, world, owner):
        light = obj.data
        color = list(light.color)
        power = light.energy
        to_world = Z_UP_TO_Y_UP @ world
        if light.type == "POINT":
            if light.shadow_soft_size > 0:
                self.warn(owner, f"radius {light.shadow_soft_size:g} is not supported: "
                                 "exported as a point light (hard shadows)")
            element = ET.SubElement(self.root, "emitter", type="point")
            ET.SubElement(element, "point", name="position",
                          value=format_numbers(to_world.translation))
            ET.SubElement(element, "color", name="power",
                          value=format_numbers(c * power for c in color))
        elif light.type == "SPOT":
            if light.shadow_soft_size > 0:
                self.warn(owner, f"radius {light.shadow_soft_size:g} is not supported: "
                                 "exported as a point spot light (hard shadows)")
            element = ET.SubElement(self.root, "emitter", type="spot")
            location, rotation, _ = to_world.decompose()
            frame = Matrix.Translation(location) @ rotation.to_matrix().to_4x4() @ LIGHT_FRAME
            transform = ET.SubElement(element, "transform", name="toWorld")
            ET.SubElement(transform, "matrix", value=matrix_value(frame))
            # Cycles' spot has the intensity of a point light of the same power on its axis.
            ET.SubElement(element, "color", name="intensity",
                          value=format_numbers(c * power / (4 * math.pi) for c in color))
            cutoff = light.spot_size / 2
            # Cycles: smoothstep over cos from cos(cutoff) to cos(cutoff) + (1 - cos(cutoff))
            # * blend; nori's spot: smoothstep from cos(cutoff) to cos(beamWidth).
            cos_beam = math.cos(cutoff) + (1 - math.cos(cutoff)) * light.spot_blend
            ET.SubElement(element, "float", name="cutoffAngle",
                          value=f"{math.degrees(cutoff):.7g}")
            ET.SubElement(element, "float", name="beamWidth",
                          value=f"{math.degrees(math.acos(min(cos_beam, 1.0))):.7g}")
        elif light.type == "SUN":
            if light.angle > 0:
                self.warn(owner, f"angle {math.degrees(light.angle):g} degrees is not "
                                 "supported: exported as a directional light (hard shadows)")
            element = ET.SubElement(self.root, "emitter", type="directional")
            direction = (to_world.to_3x3() @ Vector((0, 0, -1))).normalized()
            ET.SubElement(element, "vector", name="direction", value=format_numbers(direction))
            ET.SubElement(element, "color", name="irradiance",
                          value=format_numbers(c * power for c in color))
        elif light.type == "AREA":
            self.export_area_light(light, to_world, color, power, owner)
        else:
            self.warn(owner, f"light type {light.type} is not supported: not exported")

    def export_area_light(self, light, to_world, color, power, owner):
        size_x = light.size
        size_y = light.size_y if light.shape in ("RECTANGLE", "ELLIPSE") else light.size
        if light.shape in ("SQUARE", "RECTANGLE"):
            corners = [(-size_x / 2, -size_y / 2), (size_x / 2, -size_y / 2),
                       (size_x / 2, size_y / 2), (-size_x / 2, size_y / 2)]
            area = size_x * size_y
        else:  # DISK, ELLIPSE: a 64-gon of the same area
            n = 64
            scale = math.sqrt(2 * math.pi / (n * math.sin(2 * math.pi / n)))
            corners = [(scale * size_x / 2 * math.cos(2 * math.pi * k / n),
                        scale * size_y / 2 * math.sin(2 * math.pi * k / n)) for k in range(n)]
            area = math.pi * size_x * size_y / 4
        # A polygon facing -z (where Blender's area light shines), as a fan.
        name = f"light_{slug(light.name)}_{len(self.meshes)}.obj"
        path = os.path.join("meshes", name)
        os.makedirs(os.path.join(self.folder, "meshes"), exist_ok=True)
        with open(os.path.join(self.folder, path), "w") as obj:
            obj.write(f"# area light '{light.name}', exported by blender/io_scene_nori.py\n")
            for x, y in corners:
                obj.write(f"v {x:.7g} {y:.7g} 0\n")
            obj.write("vn 0 0 -1\n")
            for k in range(1, len(corners) - 1):
                # Reversed winding: the normal points along -z.
                obj.write(f"f 1//1 {k + 2}//1 {k + 1}//1\n")
        self.meshes[("light", light.name, len(self.meshes))] = path
        mesh = ET.SubElement(self.root, "mesh", type="obj")
        ET.SubElement(mesh, "string", name="filename", value=path)
        transform = ET.SubElement(mesh, "transform", name="toWorld")
        ET.SubElement(transform, "matrix", value=matrix_value(to_world))
        bsdf = ET.SubElement(mesh, "bsdf", type="diffuse")
        ET.SubElement(bsdf, "color", name="albedo", value="0, 0, 0")
        emitter = ET.SubElement(mesh, "emitter", type="area")
        # Cycles: an area light of power P has radiance P / (4 A) (measured; not P / (pi A)).
        ET.SubElement(emitter, "color", name="radiance",
                      value=format_numbers(c * power / (4 * area) for c in color))

    # --- meshes ------------------------------------------------------------------------

    def export_mesh(self, obj, world, owner):
        original = obj.original
        # A mesh datablock is written once, whoever uses it (linked duplicates, particle
        # and collection instances); objects with modifiers get their own evaluated copy.
        if original.type == "MESH" and len(original.modifiers) == 0:
            key = ("mesh", original.data.name)
        else:
            key = ("object", original.name)
        slots = [slot.material for slot in original.material_slots] or [None]
        files = self.write_obj(obj, key, len(slots), owner)
        if files is None:
            return
        materials = tuple(slots[min(index, len(slots) - 1)] for index, _ in files)
        group_key = (key, tuple(m.name if m else None for m in materials))
        self.placements.setdefault(group_key, []).append(
            (files, materials, matrix_value(Z_UP_TO_Y_UP @ world), owner))

    def export_placements(self):
        """A geometry placed once becomes <mesh type="obj"> elements with their toWorld; one
        placed several times (linked duplicates, particle and collection instances) a
        shape group, written once, and an instance per placement, so that nori builds
        its BVH once. Emissive geometry and volumes stay separate copies: nori's
        instances neither emit nor bound media."""
        for number, placements in enumerate(self.placements.values()):
            files, materials, _, owner = placements[0]
            group = None
            if len(placements) > 1:
                group = ET.Element("mesh", type="shapegroup", id=f"group{number}")
                for (_, path), material in zip(files, materials):
                    mesh = ET.SubElement(group, "mesh", type="obj")
                    ET.SubElement(mesh, "string", name="filename", value=path)
                    self.export_material(mesh, material, owner)
                if group.find("mesh/emitter") is not None or group.find("mesh/medium") is not None:
                    group = None
            if group is not None:
                self.root.append(group)
                for _, _, transform_value, _ in placements:
                    instance = ET.SubElement(self.root, "mesh", type="instance")
                    ET.SubElement(instance, "ref", id=group.get("id"))
                    transform = ET.SubElement(instance, "transform", name="toWorld")
                    ET.SubElement(transform, "matrix", value=transform_value)
                continue
            for files, materials, transform_value, owner in placements:
                for (_, path), material in zip(files, materials):
                    mesh = ET.SubElement(self.root, "mesh", type="obj")
                    ET.SubElement(mesh, "string", name="filename", value=path)
                    transform = ET.SubElement(mesh, "transform", name="toWorld")
                    ET.SubElement(transform, "matrix", value=transform_value)
                    self.export_material(mesh, material, owner)

    def write_obj(self, obj, key, slot_count, owner):
        """Writes the evaluated mesh's triangles, one OBJ per material index used; returns
        [(material index, relative path)], or None for a mesh without faces."""
        cached = [(index, path) for (k, index), path in self.meshes.items() if k == key]
        if cached:
            return cached
        mesh = obj.to_mesh()
        try:
            mesh.calc_loop_triangles()
            if hasattr(mesh, "calc_normals_split"):  # Blender < 4.1
                mesh.calc_normals_split()
                loop_normal = lambda loop: mesh.loops[loop].normal
            else:
                loop_normal = lambda loop: mesh.corner_normals[loop].vector
            uv_layer = mesh.uv_layers.active  # without one, nori's default uv serve
            groups = {}
            for triangle in mesh.loop_triangles:
                groups.setdefault(triangle.material_index, []).append(triangle)
            if not groups:
                self.warn(owner, "has no faces: not exported")
                return None
            os.makedirs(os.path.join(self.folder, "meshes"), exist_ok=True)
            files = []
            for material_index, triangles in sorted(groups.items()):
                suffix = f"_{material_index}" if len(groups) > 1 else ""
                name = f"{slug(key[1])}{suffix}.obj"
                path = os.path.join("meshes", name)
                self.write_obj_group(mesh, triangles, uv_layer, loop_normal,
                                     os.path.join(self.folder, path))
                self.meshes[(key, material_index)] = path
                files.append((material_index, path))
            return files
        finally:
            obj.to_mesh_clear()

    @staticmethod
    def write_obj_group(mesh, triangles, uv_layer, loop_normal, filename):
        positions, uvs, normals = {}, {}, {}
        lines_v, lines_vt, lines_vn, lines_f = [], [], [], []

        def index_of(table, lines, prefix, value):
            key = tuple(round(v, 7) for v in value)
            if key not in table:
                table[key] = len(table) + 1
                lines.append(prefix + " ".join(f"{v:.7g}" for v in value))
            return table[key]

        for triangle in triangles:
            corners = []
            for vertex, loop in zip(triangle.vertices, triangle.loops):
                v = index_of(positions, lines_v, "v ", mesh.vertices[vertex].co)
                n = index_of(normals, lines_vn, "vn ", loop_normal(loop))
                if uv_layer is not None:
                    t = index_of(uvs, lines_vt, "vt ", uv_layer.data[loop].uv)
                    corners.append(f"{v}/{t}/{n}")
                else:
                    corners.append(f"{v}//{n}")
            lines_f.append("f " + " ".join(corners))
        with open(filename, "w") as file:
            file.write(f"# exported by blender/io_scene_nori.py\n")
            file.write("\n".join(lines_v + lines_vt + lines_vn + lines_f) + "\n")

    # --- materials ---------------------------------------------------------------------

    def export_material(self, mesh, material, owner):
        if material is None:
            # Blender renders an object without material as 0.8 grey diffuse.
            bsdf = ET.SubElement(mesh, "bsdf", type="diffuse")
            ET.SubElement(bsdf, "color", name="albedo", value="0.8, 0.8, 0.8")
            return
        owner = f"{owner}, material '{material.name}'"
        if not material.use_nodes:
            bsdf = ET.SubElement(mesh, "bsdf", type="diffuse")
            ET.SubElement(bsdf, "color", name="albedo",
                          value=format_numbers(material.diffuse_color[:3]))
            return
        output = material.node_tree.get_output_node("CYCLES")
        has_volume = output is not None and self.export_volume(mesh, output, owner)
        links = output.inputs["Surface"].links if output else []
        if not links:
            if has_volume:
                # Cycles' boundary of a volume without a surface lets light pass unbent.
                ET.SubElement(mesh, "bsdf", type="null")
                return
            self.warn(owner, "has no surface shader: exported as black")
            bsdf = ET.SubElement(mesh, "bsdf", type="diffuse")
            ET.SubElement(bsdf, "color", name="albedo", value="0, 0, 0")
            return
        if output.inputs["Displacement"].is_linked:
            self.warn(owner, "displacement is not supported: ignored")
        node = links[0].from_node
        handler = {
            "BSDF_PRINCIPLED": self.principled,
            "BSDF_DIFFUSE": self.diffuse,
            "BSDF_GLOSSY": self.glossy,
            "BSDF_GLASS": self.glass,
            "EMISSION": self.emission,
        }.get(node.type)
        if handler is None:
            self.warn(owner, f"node '{node.name}' ({node.type}) is not supported: exported as "
                             "0.8 grey diffuse")
            bsdf = ET.SubElement(mesh, "bsdf", type="diffuse")
            ET.SubElement(bsdf, "color", name="albedo", value="0.8, 0.8, 0.8")
            return
        handler(mesh, node, f"{owner}, node '{node.name}'")

    def export_volume(self, mesh, output, owner):
        """The shader behind the material output's Volume as the mesh's interior medium;
        returns whether one was written. Cycles' coefficients (kernel/svm/closure.h):
          Principled Volume  sigma_s = C d, sigma_a = max(1 - C, 0) max(1 - sqrt(A), 0) d
                             (C the colour, A the absorption colour, d the density),
                             Henyey-Greenstein phase with g = anisotropy;
          Volume Scatter     sigma_s = C d, g = anisotropy;
          Volume Absorption  sigma_a = (1 - C) d."""
        links = output.inputs["Volume"].links
        if not links:
            return False
        node = links[0].from_node
        owner = f"{owner}, node '{node.name}'"
        if node.type not in ("PRINCIPLED_VOLUME", "VOLUME_SCATTER", "VOLUME_ABSORPTION"):
            self.warn(owner, f"volume node ({node.type}) is not supported: ignored")
            return False
        color = self.value(node, "Color", owner)[:3]
        density = max(self.value(node, "Density", owner), 0.0)
        anisotropy = 0.0
        if node.type == "PRINCIPLED_VOLUME":
            absorption_color = self.value(node, "Absorption Color", owner)[:3]
            sigma_s = [c * density for c in color]
            sigma_a = [max(1 - c, 0) * max(1 - math.sqrt(max(a, 0)), 0) * density
                       for c, a in zip(color, absorption_color)]
            anisotropy = self.value(node, "Anisotropy", owner)
            if self.value(node, "Emission Strength", owner) > 0 or \
                    self.value(node, "Blackbody Intensity", owner) > 0:
                self.warn(owner, "volume emission is not supported: ignored")
        elif node.type == "VOLUME_SCATTER":
            sigma_s, sigma_a = [c * density for c in color], [0.0] * 3
            anisotropy = self.value(node, "Anisotropy", owner)
        else:
            sigma_s, sigma_a = [0.0] * 3, [max(1 - c, 0) * density for c in color]
        medium = ET.SubElement(mesh, "medium", type="homogeneous", name="interior")
        ET.SubElement(medium, "color", name="sigmaS", value=format_numbers(sigma_s))
        ET.SubElement(medium, "color", name="sigmaA", value=format_numbers(sigma_a))
        if anisotropy != 0:
            # Cycles clamps g to [-0.999, 0.999] (kernel/closure/volume.h).
            phase = ET.SubElement(medium, "phase", type="hg")
            ET.SubElement(phase, "float", name="g",
                          value=f"{min(max(anisotropy, -0.999), 0.999):.7g}")
        self.has_media = True
        return True

    def socket(self, node, name):
        if name in node.inputs:
            return node.inputs[name]
        return node.inputs[PRINCIPLED_ALIASES[name]]

    def add_parameter(self, parent, node, socket_name, parameter, owner, kind="color",
                      convert=None):
        """A constant or an image texture (an Image Texture node wired straight in)."""
        socket = self.socket(node, socket_name)
        if socket.is_linked:
            source = socket.links[0].from_node
            if source.type == "TEX_IMAGE" and source.image is not None and convert is None:
                if source.inputs["Vector"].is_linked:
                    self.warn(owner, f"the mapping of image '{source.image.name}' is not "
                                     "supported: the mesh's uv are used")
                texture = ET.SubElement(parent, "texture", type="image", name=parameter)
                ET.SubElement(texture, "string", name="filename",
                              value=self.copy_image(source.image, owner))
                linear = source.image.colorspace_settings.name in ("Non-Color", "Linear",
                                                                    "Linear Rec.709")
                ET.SubElement(texture, "string", name="colorSpace",
                              value="linear" if linear else "srgb")
                # Closest is point sampling; Linear, Cubic and Smart get nori's trilinear MIP
                # map (it filters over the pixel footprint, where Cycles' bilinear aliases).
                if source.interpolation == "Closest":
                    ET.SubElement(texture, "string", name="filter", value="nearest")
                if source.extension != "REPEAT":
                    wrap = {"EXTEND": "clamp", "MIRROR": "mirror"}.get(source.extension)
                    if wrap:
                        ET.SubElement(texture, "string", name="wrap", value=wrap)
                    else:
                        self.warn(owner, f"image extension {source.extension} is not "
                                         "supported: repeat")
                return
            self.warn(owner, f"input '{socket_name}' is driven by node '{source.name}' "
                             f"({source.type}), which is not supported: its value "
                             f"{self.describe_value(socket)} is used")
        value = socket.default_value
        if convert is not None:
            value = convert(value)
        if kind == "color":
            ET.SubElement(parent, "color", name=parameter, value=format_numbers(value[:3]))
        else:
            ET.SubElement(parent, "float", name=parameter, value=f"{value:.7g}")

    @staticmethod
    def describe_value(socket):
        value = socket.default_value
        try:
            return "(" + format_numbers(value[:3]) + ")"
        except TypeError:
            return f"{value:g}"

    def value(self, node, name, owner):
        socket = self.socket(node, name)
        if socket.is_linked:
            self.warn(owner, f"input '{name}' is driven by node "
                             f"'{socket.links[0].from_node.name}', which is not supported: "
                             f"its value {self.describe_value(socket)} is used")
        return socket.default_value

    def principled(self, mesh, node, owner):
        transmission = self.value(node, "Transmission", owner)
        if transmission >= 0.5:
            self.warn(owner, f"transmission {transmission:g} is exported as glass (dielectric); "
                             "the other inputs but Roughness and IOR are dropped")
            self.dielectric(mesh, self.value(node, "Roughness", owner),
                            self.value(node, "IOR", owner))
        else:
            if transmission > 0:
                self.warn(owner, f"transmission {transmission:g} is not supported: ignored")
            bsdf = ET.SubElement(mesh, "bsdf", type="disney")
            self.add_parameter(bsdf, node, "Base Color", "baseColor", owner)
            for socket_name, parameter in (("Metallic", "metallic"), ("Subsurface", "subsurface"),
                                           ("Specular", "specular"),
                                           ("Specular Tint", "specularTint"),
                                           ("Roughness", "roughness"),
                                           ("Anisotropic", "anisotropic"), ("Sheen", "sheen"),
                                           ("Sheen Tint", "sheenTint"),
                                           ("Clearcoat", "clearcoat")):
                if socket_name in node.inputs or socket_name in PRINCIPLED_ALIASES:
                    socket = self.socket(node, socket_name)
                    if socket.type == "VALUE":
                        self.add_parameter(bsdf, node, socket_name, parameter, owner,
                                           kind="float", convert=lambda v: min(max(v, 0.0), 1.0))
            gloss = 1.0 - self.value(node, "Clearcoat Roughness", owner)
            ET.SubElement(bsdf, "float", name="clearcoatGloss", value=f"{gloss:.7g}")
            if self.value(node, "Anisotropic Rotation", owner) != 0:
                self.warn(owner, "anisotropic rotation is not supported: ignored")
        alpha = self.value(node, "Alpha", owner)
        if alpha < 1:
            self.warn(owner, f"alpha {alpha:g} is not supported: opaque")
        if node.inputs["Normal"].is_linked:
            self.warn(owner, "a normal input is not supported: ignored")
        self.add_emission(mesh, self.value(node, "Emission", owner),
                          self.value(node, "Emission Strength", owner)
                          if "Emission Strength" in node.inputs else 1.0)

    def diffuse(self, mesh, node, owner):
        if self.value(node, "Roughness", owner) > 0:
            self.warn(owner, "Oren-Nayar roughness is not supported: Lambertian")
        bsdf = ET.SubElement(mesh, "bsdf", type="diffuse")
        self.add_parameter(bsdf, node, "Color", "albedo", owner)

    def glossy(self, mesh, node, owner):
        # Cycles' glossy BSDF reflects its colour at every angle; a conductor with eta = 1
        # and k = 2 sqrt(F0 / (1 - F0)) reflects F0 = colour at normal incidence, rising
        # toward 1 at grazing angles.
        color = [min(max(c, 0.0), 0.999) for c in self.value(node, "Color", owner)[:3]]
        k = [2 * math.sqrt(c / (1 - c)) for c in color]
        roughness = self.value(node, "Roughness", owner)
        distribution = {"BECKMANN": "beckmann"}.get(node.distribution, "ggx")
        if node.distribution not in ("GGX", "BECKMANN"):
            self.warn(owner, f"distribution {node.distribution} is exported as GGX")
        if roughness <= 0:
            bsdf = ET.SubElement(mesh, "bsdf", type="conductor")
        else:
            bsdf = ET.SubElement(mesh, "bsdf", type="roughconductor")
            ET.SubElement(bsdf, "string", name="distribution", value=distribution)
            ET.SubElement(bsdf, "float", name="alpha", value=f"{roughness * roughness:.7g}")
        ET.SubElement(bsdf, "color", name="eta", value="1, 1, 1")
        ET.SubElement(bsdf, "color", name="k", value=format_numbers(k))

    def glass(self, mesh, node, owner):
        color = self.value(node, "Color", owner)[:3]
        if min(color) < 1:
            self.warn(owner, "tinted glass is not supported: clear")
        self.dielectric(mesh, self.value(node, "Roughness", owner), self.value(node, "IOR", owner))

    @staticmethod
    def dielectric(mesh, roughness, ior):
        if roughness <= 0:
            bsdf = ET.SubElement(mesh, "bsdf", type="dielectric")
        else:
            bsdf = ET.SubElement(mesh, "bsdf", type="roughdielectric")
            ET.SubElement(bsdf, "float", name="alpha", value=f"{roughness * roughness:.7g}")
        ET.SubElement(bsdf, "float", name="intIOR", value=f"{ior:.7g}")
        ET.SubElement(bsdf, "float", name="extIOR", value="1")

    def emission(self, mesh, node, owner):
        bsdf = ET.SubElement(mesh, "bsdf", type="diffuse")
        ET.SubElement(bsdf, "color", name="albedo", value="0, 0, 0")
        self.add_emission(mesh, self.value(node, "Color", owner),
                          self.value(node, "Strength", owner))

    @staticmethod
    def add_emission(mesh, color, strength):
        radiance = [c * strength for c in color[:3]]
        if max(radiance) > 0:
            emitter = ET.SubElement(mesh, "emitter", type="area")
            ET.SubElement(emitter, "color", name="radiance", value=format_numbers(radiance))

    def copy_image(self, image, owner):
        """Copies (or saves, for packed and generated images) an image beside the scene;
        returns its path relative to the scene."""
        if image.name in self.textures:
            return self.textures[image.name]
        os.makedirs(os.path.join(self.folder, "textures"), exist_ok=True)
        source = bpy.path.abspath(image.filepath) if image.filepath else ""
        if source and os.path.isfile(source) and not image.packed_file:
            name = slug(os.path.splitext(os.path.basename(source))[0]) + \
                os.path.splitext(source)[1].lower()
            shutil.copyfile(source, os.path.join(self.folder, "textures", name))
        else:
            name = slug(image.name) + ".png"
            image.save_render(os.path.join(self.folder, "textures", name), scene=self.scene)
        path = os.path.join("textures", name)
        self.textures[image.name] = path
        return path


def horizontal_fov(camera, width, height):
    """Blender's field of view, as the horizontal angle nori's `fov` takes."""
    fit = camera.sensor_fit
    if fit == "AUTO":
        fit = "HORIZONTAL" if width >= height else "VERTICAL_WIDTH"
    if fit == "HORIZONTAL":
        return 2 * math.atan(camera.sensor_width / (2 * camera.lens))
    sensor = camera.sensor_width if fit == "VERTICAL_WIDTH" else camera.sensor_height
    vertical = 2 * math.atan(sensor / (2 * camera.lens))
    return 2 * math.atan(math.tan(vertical / 2) * width / height)


def export_scene(context, filepath, samples=64, integrator=None, max_depth=-1):
    """Exports the context's scene to filepath; returns the list of warnings. Without an
    integrator: path_mis, or volpath when the scene has volumes."""
    return Exporter(context, filepath, samples, integrator, max_depth).export()


# --- the add-on's menu entry ----------------------------------------------------------

try:
    from bpy_extras.io_utils import ExportHelper
    from bpy.props import IntProperty, StringProperty

    class ExportNori(bpy.types.Operator, ExportHelper):
        """Export the scene to nori's XML format"""
        bl_idname = "export_scene.nori"
        bl_label = "Export Nori scene"
        filename_ext = ".xml"
        filter_glob: StringProperty(default="*.xml", options={"HIDDEN"})
        samples: IntProperty(name="Samples per pixel", default=64, min=1)

        def execute(self, context):
            warnings = export_scene(context, self.filepath, self.samples)
            for warning in warnings:
                self.report({"WARNING"}, warning)
            self.report({"INFO"}, f"Exported {self.filepath} ({len(warnings)} warnings)")
            return {"FINISHED"}

    def menu_entry(self, context):
        self.layout.operator(ExportNori.bl_idname, text="Nori scene (.xml)")

    def register():
        bpy.utils.register_class(ExportNori)
        bpy.types.TOPBAR_MT_file_export.append(menu_entry)

    def unregister():
        bpy.types.TOPBAR_MT_file_export.remove(menu_entry)
        bpy.utils.unregister_class(ExportNori)
except ImportError:  # outside Blender's UI modules
    pass
