#!/usr/bin/env python3
"""Writes vplab's scene set, assets/scenes/<name>.gltf: small glTF 2.0 files with the buffer embedded as a base64 data
URI, a camera, and named nodes and materials. Standard library only; the output is byte-for-byte deterministic.

Usage: python3 scripts/make_scenes.py [--out DIR]
The facts (Cornell box data, reflectances, emission) come from the project's scene notes; see docs/scenes.md.
"""

import argparse
import base64
import json
import math
import os
import struct

# --- small vector helpers ------------------------------------------------------------------------------------------


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def add(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def scale(a, s):
    return (a[0] * s, a[1] * s, a[2] * s)


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def normalize(a):
    n = math.sqrt(dot(a, a))
    return (a[0] / n, a[1] / n, a[2] / n)


def newell_normal(quad):
    """Unit normal of a (possibly slightly non-planar) polygon, following its vertex order (Newell's method)."""
    n = [0.0, 0.0, 0.0]
    for i, p in enumerate(quad):
        q = quad[(i + 1) % len(quad)]
        n[0] += (p[1] - q[1]) * (p[2] + q[2])
        n[1] += (p[2] - q[2]) * (p[0] + q[0])
        n[2] += (p[0] - q[0]) * (p[1] + q[1])
    return normalize(tuple(n))


def orient(quad, wanted):
    """Returns the quad in the vertex order whose counter-clockwise normal points along `wanted`."""
    return quad if dot(newell_normal(quad), wanted) > 0.0 else list(reversed(quad))


def r6(x):
    """Rounds to 6 decimals (micrometres for positions) so that the JSON text is stable and short."""
    v = round(x, 6)
    return 0.0 if v == 0.0 else v


# --- glTF writer ---------------------------------------------------------------------------------------------------


class Gltf:
    def __init__(self, name, extras):
        self.name = name
        self.extras = extras
        self.buffer = bytearray()
        self.views = []
        self.accessors = []
        self.meshes = []
        self.nodes = []
        self.materials = []
        self.material_index = {}
        self.cameras = []
        self.lights = []
        self.extensions_used = set()

    def _view(self, data, target):
        while len(self.buffer) % 4:
            self.buffer.append(0)
        self.views.append({"buffer": 0, "byteOffset": len(self.buffer), "byteLength": len(data), "target": target})
        self.buffer.extend(data)
        return len(self.views) - 1

    def _accessor(self, view, component_type, count, type_, extra=None):
        a = {"bufferView": view, "componentType": component_type, "count": count, "type": type_}
        if extra:
            a.update(extra)
        self.accessors.append(a)
        return len(self.accessors) - 1

    def material(self, name, base_color, metallic=0.0, roughness=1.0, specular=None, emission=None):
        """Adds a material once; `emission` is radiance, written as a normalised emissiveFactor times
        KHR_materials_emissive_strength so that factors stay in [0, 1] as glTF requires."""
        if name in self.material_index:
            return self.material_index[name]
        m = {
            "name": name,
            "pbrMetallicRoughness": {
                "baseColorFactor": [r6(c) for c in base_color] + [1.0],
                "metallicFactor": metallic,
                "roughnessFactor": roughness,
            },
        }
        ext = {}
        if specular is not None:
            ext["KHR_materials_specular"] = {"specularFactor": specular}
        if emission is not None:
            peak = max(emission)
            m["emissiveFactor"] = [r6(c / peak) for c in emission]
            if peak != 1.0:
                ext["KHR_materials_emissive_strength"] = {"emissiveStrength": peak}
        if ext:
            m["extensions"] = ext
            self.extensions_used.update(ext.keys())
        self.materials.append(m)
        self.material_index[name] = len(self.materials) - 1
        return self.material_index[name]

    def mesh_node(self, name, quads, material):
        """One node + mesh of quads (each quad already oriented); per-quad Newell normals, u16 indices."""
        positions, normals, indices = [], [], []
        for quad in quads:
            n = newell_normal(quad)
            base = len(positions)
            for p in quad:
                positions.append(tuple(r6(c) for c in p))
                normals.append(tuple(r6(c) for c in n))
            indices += [base, base + 1, base + 2, base, base + 2, base + 3]
        pos_view = self._view(b"".join(struct.pack("<3f", *p) for p in positions), 34962)
        nrm_view = self._view(b"".join(struct.pack("<3f", *n) for n in normals), 34962)
        idx_view = self._view(struct.pack("<%dH" % len(indices), *indices), 34963)
        # Bounds from the float32 values actually stored, as the spec requires for POSITION.
        stored = [struct.unpack("<3f", struct.pack("<3f", *p)) for p in positions]
        lo = [min(p[i] for p in stored) for i in range(3)]
        hi = [max(p[i] for p in stored) for i in range(3)]
        pos = self._accessor(pos_view, 5126, len(positions), "VEC3", {"min": lo, "max": hi})
        nrm = self._accessor(nrm_view, 5126, len(normals), "VEC3")
        idx = self._accessor(idx_view, 5123, len(indices), "SCALAR")
        self.meshes.append({"name": name, "primitives": [
            {"attributes": {"POSITION": pos, "NORMAL": nrm}, "indices": idx, "material": material, "mode": 4}]})
        self.nodes.append({"name": name, "mesh": len(self.meshes) - 1})

    def camera_node(self, name, position, target, yfov, znear=0.01, zfar=100.0):
        """A perspective camera at `position` looking at `target` (+y up), written as a node matrix: glTF cameras
        look down their local -Z."""
        forward = normalize(sub(target, position))
        right = normalize(cross(forward, (0.0, 1.0, 0.0)))
        up = cross(right, forward)
        back = scale(forward, -1.0)
        matrix = [*right, 0.0, *up, 0.0, *back, 0.0, *position, 1.0]
        self.cameras.append({"name": name, "type": "perspective",
                             "perspective": {"aspectRatio": 1.0, "yfov": yfov, "znear": znear, "zfar": zfar}})
        self.nodes.append({"name": name, "camera": len(self.cameras) - 1, "matrix": [r6(v) for v in matrix]})

    def medium_node(self, name, lower, upper, sigma_a, sigma_s, g):
        """A VPLAB_participating_media box (docs/scenes.md) spanning the axis-aligned box [lower, upper]: the node's
        translation is the centre and its scale the half sizes, so the cube [-1, 1]^3 maps onto it."""
        centre = [r6(0.5 * (lo + hi)) for lo, hi in zip(lower, upper)]
        half = [r6(0.5 * (hi - lo)) for lo, hi in zip(lower, upper)]
        medium = {"sigmaA": [r6(c) for c in sigma_a], "sigmaS": [r6(c) for c in sigma_s], "g": g}
        self.nodes.append({"name": name, "translation": centre, "scale": half,
                           "extensions": {"VPLAB_participating_media": medium}})
        self.extensions_used.add("VPLAB_participating_media")

    def smoke_node(self, name, uri, translation, uniform_scale, sigma_a, sigma_s, g, density_scale=1.0):
        """A VPLAB_participating_media density grid (docs/scenes.md): the OpenVDB file's own transform gives its voxels'
        positions in the node's frame, which the node's translation and uniform scale place."""
        medium = {"sigmaA": [r6(c) for c in sigma_a], "sigmaS": [r6(c) for c in sigma_s], "g": g,
                  "density": {"uri": uri, "grid": "density", "scale": density_scale}}
        self.nodes.append({"name": name, "translation": [r6(c) for c in translation], "scale": [uniform_scale] * 3,
                           "extensions": {"VPLAB_participating_media": medium}})
        self.extensions_used.add("VPLAB_participating_media")

    def spot_light_node(self, name, position, target, intensity, inner, outer, colour=(1.0, 1.0, 1.0)):
        """A KHR_lights_punctual spot light (intensity in candela) at `position` aimed at `target`: spot lights shine
        down their node's local -Z, so the node matrix is built like a camera's."""
        forward = normalize(sub(target, position))
        right = normalize(cross(forward, (0.0, 1.0, 0.0)))
        up = cross(right, forward)
        back = scale(forward, -1.0)
        matrix = [*right, 0.0, *up, 0.0, *back, 0.0, *position, 1.0]
        self.lights.append({"name": name, "type": "spot", "color": list(colour), "intensity": intensity,
                            "spot": {"innerConeAngle": inner, "outerConeAngle": outer}})
        self.nodes.append({"name": name, "matrix": [r6(v) for v in matrix],
                           "extensions": {"KHR_lights_punctual": {"light": len(self.lights) - 1}}})
        self.extensions_used.add("KHR_lights_punctual")

    def point_light_node(self, name, position, intensity, colour=(1.0, 1.0, 1.0)):
        """A KHR_lights_punctual point light (intensity in candela) at `position`."""
        self.lights.append({"name": name, "type": "point", "color": list(colour), "intensity": intensity})
        self.nodes.append({"name": name, "translation": [r6(c) for c in position],
                           "extensions": {"KHR_lights_punctual": {"light": len(self.lights) - 1}}})
        self.extensions_used.add("KHR_lights_punctual")

    def camera_node_rotated(self, name, position, rotation_xyzw, yfov, znear=0.01, zfar=100.0):
        self.cameras.append({"name": name, "type": "perspective",
                             "perspective": {"aspectRatio": 1.0, "yfov": yfov, "znear": znear, "zfar": zfar}})
        self.nodes.append({"name": name, "camera": len(self.cameras) - 1, "translation": [r6(v) for v in position],
                           "rotation": list(rotation_xyzw)})

    def to_json(self):
        uri = "data:application/octet-stream;base64," + base64.b64encode(bytes(self.buffer)).decode("ascii")
        doc = {
            "asset": {"version": "2.0", "generator": "vplab scripts/make_scenes.py", "extras": self.extras},
            "scene": 0,
            "scenes": [{"name": self.name, "nodes": list(range(len(self.nodes)))}],
            "nodes": self.nodes,
            "meshes": self.meshes,
            "materials": self.materials,
            "cameras": self.cameras,
            "accessors": self.accessors,
            "bufferViews": self.views,
            "buffers": [{"byteLength": len(self.buffer), "uri": uri}],
        }
        if self.lights:
            doc["extensions"] = {"KHR_lights_punctual": {"lights": self.lights}}
        if self.extensions_used:
            doc["extensionsUsed"] = sorted(self.extensions_used)
        return json.dumps(doc, indent=1, sort_keys=False) + "\n"


# --- Cornell box (official measured data, millimetres in the table, metres in the file) ---------------------------

MM = 0.001
WHITE = (0.738, 0.736, 0.737)
RED = (0.475, 0.045, 0.049)
GREEN = (0.087, 0.399, 0.084)
LIGHT_RADIANCE = (17.26, 11.43, 3.06)
BOX_CENTRE = (278.0 * MM, 274.4 * MM, 279.6 * MM)
CEILING_Y = 548.8 * MM


def mm(points):
    return [tuple(c * MM for c in p) for p in points]


WALLS = {
    "floor": mm([(552.8, 0, 0), (0, 0, 0), (0, 0, 559.2), (549.6, 0, 559.2)]),
    "ceiling": mm([(556, 548.8, 0), (556, 548.8, 559.2), (0, 548.8, 559.2), (0, 548.8, 0)]),
    "back-wall": mm([(549.6, 0, 559.2), (0, 0, 559.2), (0, 548.8, 559.2), (556, 548.8, 559.2)]),
    "right-wall": mm([(0, 0, 559.2), (0, 0, 0), (0, 548.8, 0), (0, 548.8, 559.2)]),
    "left-wall": mm([(552.8, 0, 0), (549.6, 0, 559.2), (556, 548.8, 559.2), (556, 548.8, 0)]),
}
WALL_COLOURS = {"floor": "white", "ceiling": "white", "back-wall": "white", "right-wall": "green", "left-wall": "red"}
LIGHT_QUAD = [(343, 548.8, 227), (343, 548.8, 332), (213, 548.8, 332), (213, 548.8, 227)]
SHORT_BLOCK = [
    [(130, 165, 65), (82, 165, 225), (240, 165, 272), (290, 165, 114)],
    [(290, 0, 114), (290, 165, 114), (240, 165, 272), (240, 0, 272)],
    [(130, 0, 65), (130, 165, 65), (290, 165, 114), (290, 0, 114)],
    [(82, 0, 225), (82, 165, 225), (130, 165, 65), (130, 0, 65)],
    [(240, 0, 272), (240, 165, 272), (82, 165, 225), (82, 0, 225)],
]
TALL_BLOCK = [
    [(423, 330, 247), (265, 330, 296), (314, 330, 456), (472, 330, 406)],
    [(423, 0, 247), (423, 330, 247), (472, 330, 406), (472, 0, 406)],
    [(472, 0, 406), (472, 330, 406), (314, 330, 456), (314, 0, 456)],
    [(314, 0, 456), (314, 330, 456), (265, 330, 296), (265, 0, 296)],
    [(265, 0, 296), (265, 330, 296), (423, 330, 247), (423, 0, 247)],
]


def centroid(points):
    s = (0.0, 0.0, 0.0)
    for p in points:
        s = add(s, p)
    return scale(s, 1.0 / len(points))


def block_quads(faces):
    """Block faces oriented outward: away from the block's centroid (mid-height)."""
    faces = [mm(f) for f in faces]
    top = faces[0]
    c = centroid(top)
    c = (c[0], c[1] * 0.5, c[2])
    return [orient(f, sub(centroid(f), c)) for f in faces]


def cornell(name, variant, extras_more=None, light_on=True):
    extras = {"units": "metres", "source": "Cornell Program of Computer Graphics, Cornell Box data",
              "triangles": 32, "emissiveTriangles": 2 if light_on else 0}
    if light_on:
        extras.update({"lightRadianceR": LIGHT_RADIANCE[0], "lightRadianceG": LIGHT_RADIANCE[1],
                       "lightRadianceB": LIGHT_RADIANCE[2]})
    extras.update(extras_more or {})
    g = Gltf(name, extras)
    # The measured materials are pure Lambert: no specular lobe at all.
    mats = {
        "white": g.material("white", WHITE, 0.0, 1.0, specular=0.0),
        "red": g.material("red", RED, 0.0, 1.0, specular=0.0),
        "green": g.material("green", GREEN, 0.0, 1.0, specular=0.0),
    }
    light = g.material("light", (0.78, 0.78, 0.78), 0.0, 1.0, specular=0.0,
                       emission=LIGHT_RADIANCE if light_on else None)
    for wall, quad in WALLS.items():
        material = mats[WALL_COLOURS[wall]]
        if variant == "glossy" and wall == "floor":
            # A metallic GGX floor tinted like the white paint: glossy interreflections, what VSLs are for.
            material = g.material("glossy-floor", WHITE, 1.0, 0.25)
        g.mesh_node(wall, [orient(quad, sub(BOX_CENTRE, centroid(quad)))], material)
    g.mesh_node("short-block", block_quads(SHORT_BLOCK), mats["white"])
    tall = mats["white"]
    if variant == "glossy":
        tall = g.material("glossy-block", WHITE, 0.0, 0.2, specular=1.0)
    g.mesh_node("tall-block", block_quads(TALL_BLOCK), tall)

    if variant == "indirect":
        # Lowered 10 cm and turned to face the ceiling: the camera sees no surface lit directly except the ceiling.
        y, facing = CEILING_Y - 0.0005 - 0.1, (0.0, 1.0, 0.0)
    else:
        y, facing = CEILING_Y - 0.0005, (0.0, -1.0, 0.0)
    quad = [(p[0] * MM, y, p[2] * MM) for p in LIGHT_QUAD]
    g.mesh_node("light", [orient(quad, facing)], light)

    # Official camera: (278, 273, -800) mm looking +z, 35 mm lens on a 25 mm film. Rotating the glTF camera
    # (which looks down -Z) by pi about +Y makes it look down +Z.
    g.camera_node_rotated("camera", (0.278, 0.273, -0.8), [0.0, 1.0, 0.0, 0.0], 2.0 * math.atan(12.5 / 35.0))
    return g


# --- Cornell box with fog ------------------------------------------------------------------------------------------

# Bluish haze: scattering rises toward blue (as in small-particle haze), absorption is small and grey, and the box
# is about one mean free path across (optical depth 0.7 to 1.1 over its 0.55 m), so the light's cone, the blocks'
# shadows through the air and the colour shift all show. g = 0.3: mildly forward scattering.
CORNELL_FOG_SIGMA_A = (0.1, 0.1, 0.1)
CORNELL_FOG_SIGMA_S = (1.2, 1.5, 1.9)
CORNELL_FOG_G = 0.3
# 1 mm inside the walls (the left wall leans: its nearest point is at x = 549.6 mm), and below the light.
CORNELL_FOG_LOWER = (0.001, 0.001, 0.001)
CORNELL_FOG_UPPER = (0.5486, 0.5478, 0.5582)


def cornell_fog():
    sigma_t = [a + s for a, s in zip(CORNELL_FOG_SIGMA_A, CORNELL_FOG_SIGMA_S)]
    width = CORNELL_FOG_UPPER[0] - CORNELL_FOG_LOWER[0]
    extras = {"fogSigmaTBlue": sigma_t[2], "fogOpticalDepthAcrossBlue": r6(sigma_t[2] * width), "fogG": CORNELL_FOG_G}
    g = cornell("cornell-fog", "plain", extras)
    g.medium_node("fog", CORNELL_FOG_LOWER, CORNELL_FOG_UPPER, CORNELL_FOG_SIGMA_A, CORNELL_FOG_SIGMA_S, CORNELL_FOG_G)
    return g


# --- Cornell box lit by a point light in forward-scattering fog ----------------------------------------------------

# The area light is off (its panel stays, not emitting); a 0.5 cd point light hangs in grey, strongly forward-scattering
# fog that fills the box 5 mm inside the walls. Next-event estimation from scattering points near the light carries a
# 1/d^2 that free-flight sampling does not follow: the scene equiangular sampling is for (docs/theory.md §24).
POINT_FOG_SIGMA_A = (0.05, 0.05, 0.05)
POINT_FOG_SIGMA_S = (0.8, 0.8, 0.8)
POINT_FOG_G = 0.7
POINT_FOG_LOWER = (0.005, 0.005, 0.005)
POINT_FOG_UPPER = (0.5446, 0.5438, 0.5542)  # 5 mm inside the left wall's nearest point, the ceiling, the back wall
POINT_FOG_LIGHT = (0.278, 0.42, 0.28)
POINT_FOG_INTENSITY = 0.5


def cornell_point_fog():
    extras = {"lightIntensity": POINT_FOG_INTENSITY, "fogSigmaT": POINT_FOG_SIGMA_A[0] + POINT_FOG_SIGMA_S[0],
              "fogG": POINT_FOG_G}
    g = cornell("cornell-point-fog", "plain", extras, light_on=False)
    g.point_light_node("point-light", POINT_FOG_LIGHT, POINT_FOG_INTENSITY)
    g.medium_node("fog", POINT_FOG_LOWER, POINT_FOG_UPPER, POINT_FOG_SIGMA_A, POINT_FOG_SIGMA_S, POINT_FOG_G)
    return g


# --- Cornell box with smoke ----------------------------------------------------------------------------------------

# The plume of scripts/make_smoke.py (32 x 48 x 32 voxels of 1 cm, density in [0, 1]) at 0.8 scale, rising from the
# floor in the free corner in front of the tall block: 0.26 m wide, 0.39 m high. Per unit density it scatters like
# dense smoke, slightly more toward blue, albedo about 0.9: optical depth about 3 straight across it, 9 up through
# it (the bound removes much more energy in it than on the walls, as in the course's smoke).
CORNELL_SMOKE_SIGMA_A = (5.0, 5.0, 5.0)
CORNELL_SMOKE_SIGMA_S = (45.0, 50.0, 55.0)
CORNELL_SMOKE_G = 0.3
CORNELL_SMOKE_SCALE = 0.8
CORNELL_SMOKE_CENTRE = (0.41, 0.135)  # x, z of the plume's axis at its base (metres)


def cornell_smoke():
    half = 0.155 * CORNELL_SMOKE_SCALE  # the grid's voxels span [0, 0.31] m across in its own frame
    translation = (CORNELL_SMOKE_CENTRE[0] - half, 0.001 + 0.01 * CORNELL_SMOKE_SCALE, CORNELL_SMOKE_CENTRE[1] - half)
    extras = {"smokeSigmaTMaxBlue": CORNELL_SMOKE_SIGMA_A[2] + CORNELL_SMOKE_SIGMA_S[2], "smokeG": CORNELL_SMOKE_G}
    g = cornell("cornell-smoke", "plain", extras)
    g.smoke_node("smoke", "cornell-smoke.vdb", translation, CORNELL_SMOKE_SCALE, CORNELL_SMOKE_SIGMA_A,
                 CORNELL_SMOKE_SIGMA_S, CORNELL_SMOKE_G)
    return g


# --- furnace --------------------------------------------------------------------------------------------------------

FURNACE_ALBEDO = 0.5
FURNACE_EMISSION = 1.0


def furnace():
    extras = {"albedo": FURNACE_ALBEDO, "emission": FURNACE_EMISSION,
              "expectedRadiance": FURNACE_EMISSION / (1.0 - FURNACE_ALBEDO), "units": "metres"}
    g = Gltf("furnace", extras)
    m = g.material("furnace-wall", (FURNACE_ALBEDO,) * 3, 0.0, 1.0, specular=0.0, emission=(FURNACE_EMISSION,) * 3)
    # Cube [-1, 1]^3, each face split 2 x 2 so the mesh has interior edges and T-free creases at every corner.
    n = 2
    for axis, axis_name in enumerate("xyz"):
        u_axis, v_axis = (axis + 1) % 3, (axis + 2) % 3
        for sign, sign_name in ((-1.0, "neg"), (1.0, "pos")):
            quads = []
            for i in range(n):
                for j in range(n):
                    u0, u1 = -1.0 + 2.0 * i / n, -1.0 + 2.0 * (i + 1) / n
                    v0, v1 = -1.0 + 2.0 * j / n, -1.0 + 2.0 * (j + 1) / n
                    quad = []
                    for u, v in ((u0, v0), (u1, v0), (u1, v1), (u0, v1)):
                        p = [0.0, 0.0, 0.0]
                        p[axis], p[u_axis], p[v_axis] = sign, u, v
                        quad.append(tuple(p))
                    inward = [0.0, 0.0, 0.0]
                    inward[axis] = -sign
                    quads.append(orient(quad, tuple(inward)))
            g.mesh_node("wall-%s%s" % (sign_name, axis_name), quads, m)
    # Inside, looking into the (-1, -1, -1) corner: three creases meet in the middle of the picture.
    g.camera_node("camera", (0.5, 0.4, 0.6), (-1.0, -1.0, -1.0), math.radians(70.0))
    return g


# --- two rooms ------------------------------------------------------------------------------------------------------

ROOM_W, ROOM_H, ROOM_D = 4.0, 2.5, 4.0  # per-room interior size in x, y, z (metres)
WALL_T = 0.1                             # thickness of the shared wall
DOOR_Z0, DOOR_Z1, DOOR_H = 1.5, 2.5, 2.0  # door opening in the shared wall
TWO_ROOMS_RADIANCE = 10.0


def box_quad(axis, value, a0, a1, b0, b1, inward):
    """Axis-aligned rectangle at coordinate `value` on `axis`, spanning [a0, a1] x [b0, b1] on the other two axes
    (in cyclic order), facing `inward` (+1 or -1 along the axis)."""
    ua, va = (axis + 1) % 3, (axis + 2) % 3
    quad = []
    for a, b in ((a0, b0), (a1, b0), (a1, b1), (a0, b1)):
        p = [0.0, 0.0, 0.0]
        p[axis], p[ua], p[va] = value, a, b
        quad.append(tuple(p))
    n = [0.0, 0.0, 0.0]
    n[axis] = inward
    return orient(quad, tuple(n))


def wall_with_door(x, facing):
    """The shared wall's face at x, facing +x or -x, as three quads around the door opening.
    Axis 0 (x): the other two in cyclic order are y (a) and z (b)."""
    return [
        box_quad(0, x, 0.0, ROOM_H, 0.0, DOOR_Z0, facing),
        box_quad(0, x, 0.0, ROOM_H, DOOR_Z1, ROOM_D, facing),
        box_quad(0, x, DOOR_H, ROOM_H, DOOR_Z0, DOOR_Z1, facing),
    ]


def two_rooms():
    extras = {"units": "metres", "lightRadiance": TWO_ROOMS_RADIANCE, "roomAMaxX": ROOM_W,
              "roomBMinX": ROOM_W + WALL_T}
    g = Gltf("two-rooms", extras)
    white = g.material("white", (0.75, 0.75, 0.75), 0.0, 1.0, specular=0.0)
    light = g.material("ceiling-light", (0.75, 0.75, 0.75), 0.0, 1.0, specular=0.0,
                       emission=(TWO_ROOMS_RADIANCE,) * 3)
    xa0, xa1 = 0.0, ROOM_W
    xb0, xb1 = ROOM_W + WALL_T, 2.0 * ROOM_W + WALL_T
    for room, x0, x1 in (("room-a", xa0, xa1), ("room-b", xb0, xb1)):
        # Axis 1 (y): other axes z (a), x (b). Axis 2 (z): other axes x (a), y (b).
        quads = [
            box_quad(1, 0.0, 0.0, ROOM_D, x0, x1, 1.0),       # floor
            box_quad(1, ROOM_H, 0.0, ROOM_D, x0, x1, -1.0),   # ceiling
            box_quad(2, 0.0, x0, x1, 0.0, ROOM_H, 1.0),       # near wall (z = 0)
            box_quad(2, ROOM_D, x0, x1, 0.0, ROOM_H, -1.0),   # far wall (z = depth)
        ]
        if room == "room-a":
            quads.append(box_quad(0, x0, 0.0, ROOM_H, 0.0, ROOM_D, 1.0))  # outer wall
            quads += wall_with_door(x1, -1.0)
        else:
            quads.append(box_quad(0, x1, 0.0, ROOM_H, 0.0, ROOM_D, -1.0))
            quads += wall_with_door(x0, 1.0)
        g.mesh_node(room, quads, white)
    # The door's reveal: the shared wall's thickness, facing into the opening.
    jambs = [
        box_quad(2, DOOR_Z0, xa1, xb0, 0.0, DOOR_H, 1.0),
        box_quad(2, DOOR_Z1, xa1, xb0, 0.0, DOOR_H, -1.0),
        box_quad(1, DOOR_H, DOOR_Z0, DOOR_Z1, xa1, xb0, -1.0),
    ]
    g.mesh_node("door-reveal", jambs, white)
    # A 1 m^2 panel 0.5 mm below room A's ceiling, facing down.
    cx, cz, half = 0.5 * ROOM_W, 0.5 * ROOM_D, 0.5
    g.mesh_node("ceiling-light", [box_quad(1, ROOM_H - 0.0005, cz - half, cz + half, cx - half, cx + half, -1.0)],
                light)
    # In room B's far corner, looking at the door.
    g.camera_node("camera", (xb1 - 0.4, 1.5, ROOM_D - 0.4), (xa1, 1.0, 0.5 * (DOOR_Z0 + DOOR_Z1)), math.radians(60.0))
    return g


# --- fog shaft ------------------------------------------------------------------------------------------------------

SHAFT_W, SHAFT_H, SHAFT_D = 4.0, 3.0, 4.0        # room interior in x, y, z (metres)
SHAFT_WALL_T = 0.1                                # thickness of the wall with the window (x = SHAFT_W)
SHAFT_WIN_Y0, SHAFT_WIN_Y1 = 1.6, 2.8             # window opening in that wall
SHAFT_WIN_Z0, SHAFT_WIN_Z1 = 1.4, 2.6
SHAFT_LIGHT_POS = (6.0, 4.2, 2.0)                 # outside, above the window
SHAFT_LIGHT_INTENSITY = 400.0                     # candela
SHAFT_LIGHT_CONES = (0.12, 0.22)                  # inner, outer (radians): a little wider than the window
# Grey fog, optical depth 0.76 across the room's 4 m, albedo 0.84; g = 0.5 throws most scattered light onward along
# the shaft, so it looks brighter from the floor end than from the side.
SHAFT_FOG_SIGMA_A = (0.03, 0.03, 0.03)
SHAFT_FOG_SIGMA_S = (0.16, 0.16, 0.16)
SHAFT_FOG_G = 0.5


def fog_shaft():
    window_centre = (SHAFT_W + 0.5 * SHAFT_WALL_T, 0.5 * (SHAFT_WIN_Y0 + SHAFT_WIN_Y1),
                     0.5 * (SHAFT_WIN_Z0 + SHAFT_WIN_Z1))
    sigma_t = SHAFT_FOG_SIGMA_A[0] + SHAFT_FOG_SIGMA_S[0]
    extras = {"units": "metres", "lightIntensity": SHAFT_LIGHT_INTENSITY, "fogSigmaT": sigma_t,
              "fogOpticalDepthAcross": r6(sigma_t * SHAFT_W), "fogG": SHAFT_FOG_G}
    g = Gltf("fog-shaft", extras)
    white = g.material("white", (0.75, 0.75, 0.75), 0.0, 1.0, specular=0.0)
    w, h, d, x1 = SHAFT_W, SHAFT_H, SHAFT_D, SHAFT_W + SHAFT_WALL_T
    y0, y1, z0, z1 = SHAFT_WIN_Y0, SHAFT_WIN_Y1, SHAFT_WIN_Z0, SHAFT_WIN_Z1
    # Axis 0 (x): other axes y (a), z (b). Axis 1 (y): z (a), x (b). Axis 2 (z): x (a), y (b).
    room = [
        box_quad(1, 0.0, 0.0, d, 0.0, w, 1.0),    # floor
        box_quad(1, h, 0.0, d, 0.0, w, -1.0),     # ceiling
        box_quad(2, 0.0, 0.0, w, 0.0, h, 1.0),    # near wall (z = 0)
        box_quad(2, d, 0.0, w, 0.0, h, -1.0),     # far wall (z = depth)
        box_quad(0, 0.0, 0.0, h, 0.0, d, 1.0),    # wall facing the window
    ]
    g.mesh_node("room", room, white)

    def around_window(x, facing):
        """The window wall's face at x as four quads around the opening."""
        return [
            box_quad(0, x, 0.0, y0, 0.0, d, facing),
            box_quad(0, x, y1, h, 0.0, d, facing),
            box_quad(0, x, y0, y1, 0.0, z0, facing),
            box_quad(0, x, y0, y1, z1, d, facing),
        ]

    # Both faces of the window wall and the opening's reveal, so the light outside meets a solid wall with a hole.
    reveal = [
        box_quad(1, y0, z0, z1, w, x1, 1.0),
        box_quad(1, y1, z0, z1, w, x1, -1.0),
        box_quad(2, z0, w, x1, y0, y1, 1.0),
        box_quad(2, z1, w, x1, y0, y1, -1.0),
    ]
    g.mesh_node("window-wall", around_window(w, -1.0) + around_window(x1, 1.0) + reveal, white)
    g.spot_light_node("sun-spot", SHAFT_LIGHT_POS, window_centre, SHAFT_LIGHT_INTENSITY, *SHAFT_LIGHT_CONES)
    # Fog 5 mm inside the room's walls; the window's reveal stays clear.
    margin = 0.005
    g.medium_node("fog", (margin,) * 3, (w - margin, h - margin, d - margin), SHAFT_FOG_SIGMA_A, SHAFT_FOG_SIGMA_S,
                  SHAFT_FOG_G)
    # By the wall opposite the window, off to one side: the window, the shaft across the room and its patch on the
    # floor are all in view.
    g.camera_node("camera", (0.4, 1.5, 0.3), (3.0, 1.2, 2.0), math.radians(70.0))
    return g


# --- glossy counter ---------------------------------------------------------------------------------------------------

# A closed white room, 1.6 m wide, 1 m high, 1.6 m deep, with a brushed-metal counter for a floor (metallic GGX,
# roughness 0.2) and three boxes standing on it: contact reflections, the glossy transport at short distances that the
# bound removes, virtual spherical lights blur and local virtual lights bring back.
COUNTER_ROOM = ((-0.8, 0.0, -1.0), (0.8, 1.0, 0.6))
COUNTER_METAL = (0.9, 0.88, 0.85)
COUNTER_ROUGHNESS = 0.2
COUNTER_LIGHT_RADIANCE = (20.0, 19.0, 17.0)
COUNTER_LIGHT_HALF = 0.15
COUNTER_BOXES = [  # name, lower corner, upper corner, colour
    ("red-box", (-0.45, 0.0, -0.05), (-0.2, 0.3, 0.2), RED),
    ("white-tower", (-0.05, 0.0, 0.05), (0.13, 0.5, 0.23), WHITE),
    ("green-cube", (0.25, 0.0, -0.2), (0.42, 0.17, -0.03), GREEN),
]


def box_faces(lower, upper):
    """The five faces of an axis-aligned box standing on y = lower.y (no bottom), oriented outward."""
    (x0, y0, z0), (x1, y1, z1) = lower, upper
    faces = [
        [(x0, y1, z0), (x1, y1, z0), (x1, y1, z1), (x0, y1, z1)],
        [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0)],
        [(x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)],
        [(x0, y0, z0), (x0, y0, z1), (x0, y1, z1), (x0, y1, z0)],
        [(x1, y0, z0), (x1, y0, z1), (x1, y1, z1), (x1, y1, z0)],
    ]
    centre = ((x0 + x1) / 2, (y0 + y1) / 2, (z0 + z1) / 2)
    return [orient(f, sub(centroid(f), centre)) for f in faces]


def glossy_counter():
    (x0, y0, z0), (x1, y1, z1) = COUNTER_ROOM
    extras = {"units": "metres", "counterMetallic": 1.0, "counterRoughness": COUNTER_ROUGHNESS,
              "lightRadianceR": COUNTER_LIGHT_RADIANCE[0], "lightRadianceG": COUNTER_LIGHT_RADIANCE[1],
              "lightRadianceB": COUNTER_LIGHT_RADIANCE[2]}
    g = Gltf("glossy-counter", extras)
    white = g.material("white", WHITE, 0.0, 1.0, specular=0.0)
    metal = g.material("brushed-metal", COUNTER_METAL, 1.0, COUNTER_ROUGHNESS)
    light = g.material("light", (0.78, 0.78, 0.78), 0.0, 1.0, specular=0.0, emission=COUNTER_LIGHT_RADIANCE)
    centre = ((x0 + x1) / 2, (y0 + y1) / 2, (z0 + z1) / 2)
    room = {
        "walls": [
            [(x0, y1, z0), (x1, y1, z0), (x1, y1, z1), (x0, y1, z1)],
            [(x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)],
            [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0)],
            [(x0, y0, z0), (x0, y0, z1), (x0, y1, z1), (x0, y1, z0)],
            [(x1, y0, z0), (x1, y0, z1), (x1, y1, z1), (x1, y1, z0)],
        ],
    }
    g.mesh_node("walls", [orient(q, sub(centre, centroid(q))) for q in room["walls"]], white)
    g.mesh_node("counter", [orient([(x0, y0, z0), (x1, y0, z0), (x1, y0, z1), (x0, y0, z1)], (0.0, 1.0, 0.0))], metal)
    for name, lower, upper, colour in COUNTER_BOXES:
        g.mesh_node(name, box_faces(lower, upper), g.material(name, colour, 0.0, 1.0, specular=0.0))
    h, ly = COUNTER_LIGHT_HALF, y1 - 0.0005
    g.mesh_node("light", [orient([(-h, ly, -h), (h, ly, -h), (h, ly, h), (-h, ly, h)], (0.0, -1.0, 0.0))], light)
    # From near the front wall, above the counter, looking down at the boxes' feet and their reflections.
    g.camera_node("camera", (0.0, 0.6, -0.95), (-0.05, 0.08, 0.05), math.radians(50.0))
    return g


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    parser.add_argument("--out", default=os.path.join(root, "assets", "scenes"))
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    scenes = {
        "cornell-box": cornell("cornell-box", "plain"),
        "cornell-glossy": cornell("cornell-glossy", "glossy"),
        "cornell-indirect": cornell("cornell-indirect", "indirect"),
        "furnace": furnace(),
        "two-rooms": two_rooms(),
        "cornell-fog": cornell_fog(),
        "fog-shaft": fog_shaft(),
        "cornell-smoke": cornell_smoke(),
        "cornell-point-fog": cornell_point_fog(),
        "glossy-counter": glossy_counter(),
    }
    for name, g in scenes.items():
        text = g.to_json()
        path = os.path.join(args.out, name + ".gltf")
        with open(path, "w", encoding="ascii", newline="\n") as f:
            f.write(text)
        print("%-18s %6d bytes  %s" % (name, len(text), path))


if __name__ == "__main__":
    main()
