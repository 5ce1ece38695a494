"""Renders a vplab scene with Blender's Cycles, for the error-per-second comparison of docs/benchmarks.md ("Distance
sampling toward the lights"). Runs inside Blender (Debian's `blender` package, 3.4; not needed by vplab itself):

  blender -b --factory-startup --python scripts/cycles_render.py -- SCENE.gltf OUT.exr [--spp N] [--seed S]
          [--size 256] [--threads 2] [--pfm OUT.pfm]

It builds the scene from the glTF file itself (standard library JSON, no importer): the triangles of every mesh node,
Lambert materials (Diffuse BSDF, roughness 0) with the base colour, one-sided emission (emissiveFactor x
KHR_materials_emissive_strength, nothing from the back), KHR_lights_punctual point lights of radius 0 (Cycles' point
light of power P has intensity P / (4 pi): P = 4 pi I), the camera (yfov), a black world, and each homogeneous
VPLAB_participating_media box as a cube with Volume Scatter (density x colour = sigma_s, anisotropy g) plus Volume
Absorption (black, density sigma_a), marked homogeneous, distance sampling by MIS (Cycles' equiangular + distance).
Cycles settings that would bias or blur the comparison are off: no denoising, no adaptive sampling, no clamping, light
threshold 0, a 1-pixel box filter, 32 bounces of every kind. It prints the render's wall time (the render call alone,
scene sync and BVH included, Blender's start-up not) and writes the image as EXR (and PFM with --pfm, for
scripts/seed_error.py).
"""

import argparse
import base64
import json
import math
import os
import struct
import sys
import time

import bpy
import mathutils


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    parser = argparse.ArgumentParser(prog="cycles_render.py")
    parser.add_argument("scene")
    parser.add_argument("out")
    parser.add_argument("--spp", type=int, default=64)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--size", type=int, default=256)
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--pfm")
    return parser.parse_args(argv)


def load_gltf(path):
    with open(path, encoding="utf-8") as f:
        doc = json.load(f)
    buffers = []
    for b in doc["buffers"]:
        uri = b["uri"]
        if uri.startswith("data:"):
            buffers.append(base64.b64decode(uri.split(",", 1)[1]))
        else:
            with open(os.path.join(os.path.dirname(path), uri), "rb") as f:
                buffers.append(f.read())
    return doc, buffers


def accessor(doc, buffers, index):
    a = doc["accessors"][index]
    view = doc["bufferViews"][a["bufferView"]]
    data = buffers[view["buffer"]]
    offset = view.get("byteOffset", 0) + a.get("byteOffset", 0)
    comps = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}[a["type"]]
    fmt = {5126: "f", 5125: "I", 5123: "H", 5121: "B"}[a["componentType"]]
    size = struct.calcsize(fmt)
    stride = view.get("byteStride", size * comps)
    out = []
    for i in range(a["count"]):
        values = struct.unpack_from("<%d%s" % (comps, fmt), data, offset + i * stride)
        out.append(values if comps > 1 else values[0])
    return out


def node_matrix(node):
    if "matrix" in node:
        m = node["matrix"]
        return mathutils.Matrix([[m[0], m[4], m[8], m[12]], [m[1], m[5], m[9], m[13]], [m[2], m[6], m[10], m[14]],
                                 [m[3], m[7], m[11], m[15]]])
    t = mathutils.Matrix.Translation(node.get("translation", [0.0, 0.0, 0.0]))
    x, y, z, w = node.get("rotation", [0.0, 0.0, 0.0, 1.0])
    r = mathutils.Quaternion((w, x, y, z)).to_matrix().to_4x4()
    sx, sy, sz = node.get("scale", [1.0, 1.0, 1.0])
    s = mathutils.Matrix.Diagonal((sx, sy, sz, 1.0))
    return t @ r @ s


def surface_material(name, gm):
    """Lambert with the base colour; emission only on the front (the winding side), as vplab's emitters."""
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    nodes.clear()
    out = nodes.new("ShaderNodeOutputMaterial")
    diffuse = nodes.new("ShaderNodeBsdfDiffuse")
    base = gm.get("pbrMetallicRoughness", {}).get("baseColorFactor", [1.0, 1.0, 1.0, 1.0])
    diffuse.inputs["Color"].default_value = (base[0], base[1], base[2], 1.0)
    diffuse.inputs["Roughness"].default_value = 0.0
    emissive = gm.get("emissiveFactor", [0.0, 0.0, 0.0])
    strength = gm.get("extensions", {}).get("KHR_materials_emissive_strength", {}).get("emissiveStrength", 1.0)
    if max(emissive) > 0.0:
        emission = nodes.new("ShaderNodeEmission")
        emission.inputs["Color"].default_value = (emissive[0], emissive[1], emissive[2], 1.0)
        emission.inputs["Strength"].default_value = strength
        add = nodes.new("ShaderNodeAddShader")
        links.new(diffuse.outputs["BSDF"], add.inputs[0])
        links.new(emission.outputs["Emission"], add.inputs[1])
        geometry = nodes.new("ShaderNodeNewGeometry")
        mix = nodes.new("ShaderNodeMixShader")
        links.new(geometry.outputs["Backfacing"], mix.inputs["Fac"])
        links.new(add.outputs["Shader"], mix.inputs[1])
        links.new(diffuse.outputs["BSDF"], mix.inputs[2])
        links.new(mix.outputs["Shader"], out.inputs["Surface"])
    else:
        links.new(diffuse.outputs["BSDF"], out.inputs["Surface"])
    return mat


def volume_material(name, medium):
    sigma_a, sigma_s, g = medium["sigmaA"], medium["sigmaS"], medium.get("g", 0.0)
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    mat.cycles.homogeneous_volume = True
    mat.cycles.volume_sampling = "MULTIPLE_IMPORTANCE"
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    nodes.clear()
    out = nodes.new("ShaderNodeOutputMaterial")
    scatter = nodes.new("ShaderNodeVolumeScatter")
    peak = max(max(sigma_s), 1e-12)
    scatter.inputs["Color"].default_value = (sigma_s[0] / peak, sigma_s[1] / peak, sigma_s[2] / peak, 1.0)
    scatter.inputs["Density"].default_value = max(sigma_s)
    scatter.inputs["Anisotropy"].default_value = g
    if max(sigma_a) != min(sigma_a):
        raise SystemExit("only grey absorption is supported (sigmaA %s)" % sigma_a)
    absorb = nodes.new("ShaderNodeVolumeAbsorption")
    absorb.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)  # sigma_a = density x (1 - colour)
    absorb.inputs["Density"].default_value = sigma_a[0]
    add = nodes.new("ShaderNodeAddShader")
    links.new(scatter.outputs["Volume"], add.inputs[0])
    links.new(absorb.outputs["Volume"], add.inputs[1])
    links.new(add.outputs["Shader"], out.inputs["Volume"])
    return mat


def build(doc, buffers, size):
    scene = bpy.context.scene
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj, do_unlink=True)
    world = bpy.data.worlds.new("black")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
    scene.world = world
    materials = [surface_material(m.get("name", "m%d" % i), m) for i, m in enumerate(doc.get("materials", []))]
    lights = doc.get("extensions", {}).get("KHR_lights_punctual", {}).get("lights", [])
    for index, node in enumerate(doc["nodes"]):
        name = node.get("name", "node%d" % index)
        matrix = node_matrix(node)
        if "mesh" in node:
            vertices, faces, face_materials = [], [], []
            for prim in doc["meshes"][node["mesh"]]["primitives"]:
                base = len(vertices)
                vertices += [tuple(matrix @ mathutils.Vector(p)) for p in
                             accessor(doc, buffers, prim["attributes"]["POSITION"])]
                idx = accessor(doc, buffers, prim["indices"])
                faces += [(base + idx[i], base + idx[i + 1], base + idx[i + 2]) for i in range(0, len(idx), 3)]
                face_materials += [prim.get("material", 0)] * (len(idx) // 3)
            mesh = bpy.data.meshes.new(name)
            mesh.from_pydata(vertices, [], faces)
            used = sorted(set(face_materials))
            for m in used:
                mesh.materials.append(materials[m])
            for poly, m in zip(mesh.polygons, face_materials):
                poly.material_index = used.index(m)
            scene.collection.objects.link(bpy.data.objects.new(name, mesh))
        if "camera" in node:
            gc = doc["cameras"][node["camera"]]["perspective"]
            cam = bpy.data.cameras.new(name)
            cam.lens_unit = "FOV"
            cam.sensor_fit = "VERTICAL"
            cam.angle_y = gc["yfov"]
            cam.clip_start, cam.clip_end = 1e-3, 1e3
            obj = bpy.data.objects.new(name, cam)
            obj.matrix_world = matrix
            scene.collection.objects.link(obj)
            scene.camera = obj
        ext = node.get("extensions", {})
        if "KHR_lights_punctual" in ext:
            gl = lights[ext["KHR_lights_punctual"]["light"]]
            if gl["type"] != "point":
                raise SystemExit("only point lights are supported (%s)" % gl["type"])
            light = bpy.data.lights.new(name, "POINT")
            light.color = gl.get("color", [1.0, 1.0, 1.0])
            light.energy = 4.0 * math.pi * gl.get("intensity", 1.0)
            light.shadow_soft_size = 0.0
            obj = bpy.data.objects.new(name, light)
            obj.matrix_world = matrix
            scene.collection.objects.link(obj)
        if "VPLAB_participating_media" in ext:
            medium = ext["VPLAB_participating_media"]
            if "density" in medium or medium.get("fillsSpace"):
                raise SystemExit("only homogeneous media boxes are supported")
            bpy.ops.mesh.primitive_cube_add(size=2.0)
            obj = bpy.context.active_object
            obj.name = name
            obj.matrix_world = matrix
            obj.data.materials.append(volume_material(name, medium))
    scene.render.resolution_x = scene.render.resolution_y = size
    scene.render.resolution_percentage = 100


def configure(args):
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device = "CPU"
    c.samples = args.spp
    c.seed = args.seed
    c.use_denoising = False
    c.use_adaptive_sampling = False
    c.sample_clamp_direct = 0.0
    c.sample_clamp_indirect = 0.0
    c.light_sampling_threshold = 0.0
    c.blur_glossy = 0.0
    c.max_bounces = c.diffuse_bounces = c.glossy_bounces = c.transmission_bounces = 32
    c.volume_bounces = c.transparent_max_bounces = 32
    c.pixel_filter_type = "BOX"
    c.filter_width = 1.0
    scene.render.threads_mode = "FIXED"
    scene.render.threads = args.threads
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0.0
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"


def write_pfm(exr, pfm):
    image = bpy.data.images.load(os.path.abspath(exr))
    w, h = image.size
    px = list(image.pixels)
    with open(pfm, "wb") as f:
        f.write(b"PF\n%d %d\n-1.0\n" % (w, h))
        rgb = []
        for i in range(w * h):  # Blender's rows start at the bottom, as PFM's do
            rgb += px[4 * i:4 * i + 3]
        f.write(struct.pack("<%df" % len(rgb), *rgb))


def main():
    args = parse_args()
    doc, buffers = load_gltf(args.scene)
    build(doc, buffers, args.size)
    configure(args)
    start = time.time()
    bpy.ops.render.render()
    seconds = time.time() - start
    bpy.data.images["Render Result"].save_render(os.path.abspath(args.out))
    print("cycles %s: %d spp, seed %d, %dx%d, %d threads, render %.2f s" %
          (args.scene, args.spp, args.seed, args.size, args.size, args.threads, seconds))
    if args.pfm:
        write_pfm(args.out, args.pfm)


main()
