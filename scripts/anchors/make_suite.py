#!/usr/bin/env python3
"""Build the suite's own scenes (issue 28) from ../shared/assets, in both forms: glTF
(`scene.gltf` + `scene.bin`, for Caustic) and Mitsuba 3 XML (`scene.xml` + binary PLYs), with
the same float32 triangles, camera and materials.

    python3 scripts/anchors/make_suite.py [--scenes env_mesh,million] [--out assets/suite]
    python3 scripts/anchors/make_suite.py --reference million --minutes 10   # needs Mitsuba

Scenes (512x512, path tracer with unbounded depth, box pixel filter):
- `env_mesh`: the armadillo (Lambert) and the bunny (GGX conductor, F0 = 1, roughness 0.3)
  on a Lambert disk, lit only by `venice_sunset_1k.hdr` (Caustic: `--environment`, which
  suite.py passes; Mitsuba: an `envmap` emitter turned 180 degrees about +Y, because
  Caustic's lat-long map puts -Z at u = 0.5 and Mitsuba's puts it at u = 0).
- `million`: the Cornell box of ../shared/references/cornell_dragon (walls and light read
  from its PLYs) holding twelve statues, 1,199,796 triangles: four Lucys at the back, four
  armadillos, four dragons in front; one dragon is glass (smooth dielectric, index 1.5), one
  armadillo a mirror (smooth conductor, reflectance 1), one Lucy rough metal (GGX, F0 = 1,
  roughness 0.3), the rest Lambert. Copies are nodes (glTF) and `to_world` shapes (XML) over
  one mesh per model, so the files stay small (about 5 MB each form).
- `mirror_caustic`: the same box's walls and light, a glass ball (9,024 triangles, flat
  facets in both forms) high under the light and a mirror on the back wall, its top tilted 30 degrees out:
  the ball's caustic on the floor seen directly and in the mirror, light that only
  specular-diffuse-specular paths carry (issue 29's scene for photon mapping).

Materials are ones both renderers express exactly: Lambert (glTF metallic 0, roughness 1,
KHR_materials_specular 0; Mitsuba `twosided diffuse`), smooth glass (transmission 1, ior 1.5,
roughness 0; `dielectric`) and metals of reflectance 1 at every angle (metallic 1, base colour
1, so Schlick's Fresnel is 1; `conductor`/`roughconductor` with material `none`). The one
difference left: Caustic's GGX uses the height-correlated Smith G2, Mitsuba the separable
G1 G1; at alpha 0.09 it does not show: a 256-spp Caustic render of env_mesh has the rough
bunny's mean within 0.05% of the reference and its relMSE follows the 1/spp law.

The generated files are not committed (git-ignored); `reference.exr` and
`reference_stderr.exr` (512x512 half float) are. `--reference` renders them with Mitsuba
`llvm_ad_rgb` in batches of 32 spp with distinct seeds until `--minutes` run out, and writes
the per-pixel standard error of the mean from the batches' spread, so that suite.py can
subtract the reference's own noise.
"""

import argparse
import json
import math
import os
import sys
import time

import numpy as np

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
SHARED = os.path.normpath(os.path.join(ROOT, "..", "shared"))
MESHES = os.path.join(SHARED, "assets", "meshes")
ENVMAP = os.path.join(SHARED, "assets", "envmaps", "venice_sunset_1k.hdr")
CORNELL_DRAGON = os.path.join(SHARED, "references", "cornell_dragon")
SIZE = 512


# ---------------------------------------------------------------------------- mesh files

def read_obj(path):
    """Positions and fan-triangulated faces (first index of each `a/b/c` group) of an OBJ."""
    vertices, faces = [], []
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                vertices.append([float(x) for x in line.split()[1:4]])
            elif line.startswith("f "):
                idx = [int(t.split("/")[0]) for t in line.split()[1:]]
                idx = [i - 1 if i > 0 else len(vertices) + i for i in idx]
                faces.extend([idx[0], idx[k], idx[k + 1]] for k in range(1, len(idx) - 1))
    return np.array(vertices, np.float32), np.array(faces, np.uint32)


PLY_TYPES = {"float": "f4", "float32": "f4", "double": "f8", "uchar": "u1", "uint8": "u1",
             "char": "i1", "int8": "i1", "ushort": "u2", "short": "i2", "int": "i4",
             "int32": "i4", "uint": "u4", "uint32": "u4"}


def read_ply(path):
    """Positions and triangles of a binary little-endian PLY (vertex properties of any
    scalar type, faces as `list uchar int|uint`, triangles only)."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode("ascii").splitlines()
    if "format binary_little_endian 1.0" not in header:
        sys.exit(f"{path}: only binary little-endian PLY is read")
    elements, current = [], None
    for line in header:
        words = line.split()
        if words[:1] == ["element"]:
            current = [words[1], int(words[2]), []]
            elements.append(current)
        elif words[:1] == ["property"]:
            current[2].append(words[1:])
    offset, vertices, faces = end, None, None
    for name, count, props in elements:
        if name == "vertex":
            dtype = np.dtype([(p[1], "<" + PLY_TYPES[p[0]]) for p in props])
            table = np.frombuffer(data, dtype, count, offset)
            vertices = np.stack([table["x"], table["y"], table["z"]], 1).astype(np.float32)
            offset += dtype.itemsize * count
        elif name == "face":
            kind = props[0]
            if kind[:3] != ["list", "uchar", kind[2]] or kind[2] not in ("int", "uint", "int32", "uint32"):
                sys.exit(f"{path}: faces must be `list uchar int`")
            dtype = np.dtype([("n", "u1"), ("i", "<i4", 3)])
            table = np.frombuffer(data, dtype, count, offset)
            if np.any(table["n"] != 3):
                sys.exit(f"{path}: only triangles are read")
            faces = table["i"].astype(np.uint32)
            offset += dtype.itemsize * count
    return vertices, faces


def write_ply(path, vertices, faces):
    """Binary little-endian PLY: float32 x y z, faces as `list uchar int`."""
    header = ("ply\nformat binary_little_endian 1.0\ncomment generated by scripts/anchors/make_suite.py\n"
              f"element vertex {len(vertices)}\nproperty float x\nproperty float y\nproperty float z\n"
              f"element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n")
    face_table = np.empty(len(faces), np.dtype([("n", "u1"), ("i", "<i4", 3)]))
    face_table["n"], face_table["i"] = 3, faces
    with open(path, "wb") as f:
        f.write(header.encode("ascii"))
        f.write(np.ascontiguousarray(vertices, "<f4").tobytes())
        f.write(face_table.tobytes())


def stand(vertices, height=None, width=None):
    """The mesh scaled (to `height` in y, or its largest horizontal extent to `width`, the
    smaller scale when both), centred in x and z and stood on y = 0."""
    low, high = vertices.min(0), vertices.max(0)
    extent = high - low
    scales = []
    if height:
        scales.append(height / extent[1])
    if width:
        scales.append(width / max(extent[0], extent[2]))
    scale = min(scales)
    centre = np.array([(low[0] + high[0]) / 2, low[1], (low[2] + high[2]) / 2])
    return ((vertices - centre) * scale).astype(np.float32)


def disk(radius, segments=96):
    """A disk in the y = 0 plane, facing +Y (counter-clockwise seen from above)."""
    angles = np.arange(segments) * 2 * math.pi / segments
    rim = np.stack([radius * np.cos(angles), np.zeros(segments), radius * np.sin(angles)], 1)
    vertices = np.vstack([[0.0, 0.0, 0.0], rim]).astype(np.float32)
    faces = [[0, 1 + (k + 1) % segments, 1 + k] for k in range(segments)]
    return vertices, np.array(faces, np.uint32)


# ---------------------------------------------------------------------------- transforms

def yaw_translate(angle_deg, translation):
    """4x4 matrix: rotation by `angle_deg` about +Y, then the translation."""
    a = math.radians(angle_deg)
    m = np.eye(4)
    m[0, 0], m[0, 2], m[2, 0], m[2, 2] = math.cos(a), math.sin(a), -math.sin(a), math.cos(a)
    m[:3, 3] = translation
    return m


def look_at(eye, target, up):
    """Camera-to-world matrix of a glTF camera (looking down its -Z, +Y up)."""
    eye, target, up = (np.array(v, float) for v in (eye, target, up))
    forward = (target - eye) / np.linalg.norm(target - eye)
    right = np.cross(forward, up)
    right /= np.linalg.norm(right)
    true_up = np.cross(right, forward)
    m = np.eye(4)
    m[:3, 0], m[:3, 1], m[:3, 2], m[:3, 3] = right, true_up, -forward, eye
    return m


def xml_matrix(m):
    return " ".join(f"{x:.9g}" for x in m.flatten())


# ---------------------------------------------------------------------------- materials

def lambert(name, rgb):
    return {"name": name, "kind": "diffuse", "rgb": rgb}


MATERIALS_GLTF = {
    "diffuse": lambda m: {"pbrMetallicRoughness": {"baseColorFactor": list(m["rgb"]) + [1.0], "metallicFactor": 0.0,
                                                   "roughnessFactor": 1.0},
                          "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}, "doubleSided": True},
    "glass": lambda m: {"pbrMetallicRoughness": {"baseColorFactor": [1.0, 1.0, 1.0, 1.0], "metallicFactor": 0.0,
                                                 "roughnessFactor": 0.0},
                        "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0},
                                       "KHR_materials_ior": {"ior": 1.5},
                                       "KHR_materials_volume": {"thicknessFactor": 1.0}}},
    "metal": lambda m: {"pbrMetallicRoughness": {"baseColorFactor": [1.0, 1.0, 1.0, 1.0], "metallicFactor": 1.0,
                                                 "roughnessFactor": m["roughness"]}, "doubleSided": True},
    "emitter": lambda m: {"pbrMetallicRoughness": {"baseColorFactor": [0.0, 0.0, 0.0, 1.0], "metallicFactor": 0.0,
                                                   "roughnessFactor": 1.0},
                          "emissiveFactor": [c / max(m["radiance"]) for c in m["radiance"]],
                          "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": max(m["radiance"])},
                                         "KHR_materials_specular": {"specularFactor": 0.0}}},
}


def xml_bsdf(m):
    rgb = lambda v: ", ".join(f"{x:.9g}" for x in v)
    if m["kind"] == "diffuse":
        return (f'    <bsdf type="twosided" id="{m["name"]}">\n        <bsdf type="diffuse">\n'
                f'            <rgb name="reflectance" value="{rgb(m["rgb"])}"/>\n        </bsdf>\n    </bsdf>\n')
    if m["kind"] == "glass":
        return (f'    <bsdf type="dielectric" id="{m["name"]}">\n        <float name="int_ior" value="1.5"/>\n'
                '        <float name="ext_ior" value="1.0"/>\n    </bsdf>\n')
    if m["kind"] == "metal":
        alpha = m["roughness"] ** 2
        inner = ('<bsdf type="conductor">\n            <string name="material" value="none"/>\n' if alpha == 0 else
                 f'<bsdf type="roughconductor">\n            <string name="material" value="none"/>\n'
                 f'            <string name="distribution" value="ggx"/>\n'
                 f'            <float name="alpha" value="{alpha:.9g}"/>\n')
        return f'    <bsdf type="twosided" id="{m["name"]}">\n        {inner}        </bsdf>\n    </bsdf>\n'
    if m["kind"] == "emitter":
        return (f'    <bsdf type="diffuse" id="{m["name"]}">\n'
                '        <rgb name="reflectance" value="0, 0, 0"/>\n    </bsdf>\n')
    raise ValueError(m["kind"])


# ---------------------------------------------------------------------------- writers

def write_scene(folder, name, description, meshes, instances, materials, camera, environment=None):
    """Write `scene.gltf` + `scene.bin` and `scene.xml` + `meshes/*.ply`.

    meshes: {mesh name: (vertices, faces)}; instances: [(node name, mesh name, material name,
    4x4 matrix)]; camera: (eye, target, up, vertical fov in degrees); environment: an HDR
    path for Mitsuba's envmap emitter (Caustic gets it on the command line)."""
    os.makedirs(os.path.join(folder, "meshes"), exist_ok=True)
    by_name = {m["name"]: m for m in materials}
    material_index = {m["name"]: i for i, m in enumerate(materials)}
    blob, views, accessors, mesh_accessors = bytearray(), [], [], {}
    for mesh_name, (vertices, faces) in meshes.items():
        write_ply(os.path.join(folder, "meshes", f"{mesh_name}.ply"), vertices, faces)
        for array, target, component, kind in ((vertices, 34962, 5126, "VEC3"), (faces, 34963, 5125, "SCALAR")):
            data = np.ascontiguousarray(array, "<f4" if component == 5126 else "<u4").tobytes()
            views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(data), "target": target})
            blob += data + b"\0" * (-len(data) % 4)
            accessor = {"bufferView": len(views) - 1, "componentType": component, "type": kind,
                        "count": len(array) if kind == "VEC3" else array.size}
            if kind == "VEC3":
                accessor["min"], accessor["max"] = vertices.min(0).tolist(), vertices.max(0).tolist()
            accessors.append(accessor)
        mesh_accessors[mesh_name] = (len(accessors) - 2, len(accessors) - 1)
    gltf_meshes, mesh_index, nodes = [], {}, []
    for node_name, mesh_name, material, matrix in instances:
        key = (mesh_name, material)
        if key not in mesh_index:
            position, indices = mesh_accessors[mesh_name]
            mesh_index[key] = len(gltf_meshes)
            gltf_meshes.append({"name": f"{mesh_name}_{material}", "primitives": [
                {"attributes": {"POSITION": position}, "indices": indices, "material": material_index[material], "mode": 4}]})
        nodes.append({"name": node_name, "mesh": mesh_index[key], "matrix": matrix.T.flatten().tolist()})
    eye, target, up, fov = camera
    nodes.append({"name": "camera", "camera": 0, "matrix": look_at(eye, target, up).T.flatten().tolist()})
    gltf_materials = [dict(name=m["name"], **MATERIALS_GLTF[m["kind"]](m)) for m in materials]
    gltf = {
        "asset": {"version": "2.0", "generator": "scripts/anchors/make_suite.py"},
        "extensionsUsed": ["KHR_materials_emissive_strength", "KHR_materials_ior", "KHR_materials_specular",
                           "KHR_materials_transmission", "KHR_materials_volume"],
        "scene": 0,
        "scenes": [{"name": name, "nodes": list(range(len(nodes)))}],
        "nodes": nodes, "meshes": gltf_meshes, "materials": gltf_materials, "accessors": accessors,
        "bufferViews": views, "buffers": [{"uri": "scene.bin", "byteLength": len(blob)}],
        "cameras": [{"name": "camera", "type": "perspective", "perspective": {
            "yfov": math.radians(fov), "aspectRatio": 1.0, "znear": 0.01, "zfar": 100000.0},
            "extras": {"width": SIZE, "height": SIZE}}],
    }
    with open(os.path.join(folder, "scene.bin"), "wb") as f:
        f.write(blob)
    with open(os.path.join(folder, "scene.gltf"), "w") as f:
        json.dump(gltf, f, indent=1)
    xml = [f'<?xml version="1.0" encoding="utf-8"?>\n<!-- {description} -->\n'
           '<!-- Generated by scripts/anchors/make_suite.py; the same float32 triangles as scene.gltf,\n'
           '     flat normals (face_normals), max_depth -1 = unbounded with Russian roulette. -->\n'
           '<scene version="3.0.0">\n    <default name="spp" value="64"/>\n    <default name="seed" value="0"/>\n'
           '    <integrator type="path">\n        <integer name="max_depth" value="-1"/>\n    </integrator>\n'
           '    <sensor type="perspective">\n        <string name="fov_axis" value="y"/>\n'
           f'        <float name="fov" value="{fov:.9g}"/>\n'
           '        <float name="near_clip" value="0.01"/>\n        <float name="far_clip" value="100000"/>\n'
           '        <transform name="to_world">\n'
           f'            <lookat origin="{", ".join(map(str, eye))}" target="{", ".join(map(str, target))}" '
           f'up="{", ".join(map(str, up))}"/>\n        </transform>\n'
           '        <sampler type="independent">\n            <integer name="sample_count" value="$spp"/>\n'
           '            <integer name="seed" value="$seed"/>\n        </sampler>\n'
           '        <film type="hdrfilm">\n'
           f'            <integer name="width" value="{SIZE}"/>\n            <integer name="height" value="{SIZE}"/>\n'
           '            <rfilter type="box"/>\n            <string name="pixel_format" value="rgb"/>\n'
           '            <string name="component_format" value="float32"/>\n        </film>\n    </sensor>\n']
    xml += [xml_bsdf(m) for m in materials]
    if environment:
        rel = os.path.relpath(environment, folder)
        xml.append('    <emitter type="envmap">\n'
                   f'        <string name="filename" value="{rel}"/>\n'
                   '        <!-- Caustic: u = 0.5 + atan2(x, -z) / 2pi; Mitsuba: u = atan2(x, -z) / 2pi -->\n'
                   '        <transform name="to_world">\n            <rotate y="1" angle="180"/>\n        </transform>\n'
                   '    </emitter>\n')
    for node_name, mesh_name, material, matrix in instances:
        emitter = ""
        if by_name[material]["kind"] == "emitter":
            emitter = ('        <emitter type="area">\n'
                       f'            <rgb name="radiance" value="{", ".join(map(str, by_name[material]["radiance"]))}"/>\n'
                       '        </emitter>\n')
        transform = "" if np.allclose(matrix, np.eye(4)) else (
            f'        <transform name="to_world">\n            <matrix value="{xml_matrix(matrix)}"/>\n        </transform>\n')
        xml.append(f'    <shape type="ply" id="shape_{node_name}">\n'
                   f'        <string name="filename" value="meshes/{mesh_name}.ply"/>\n'
                   '        <boolean name="face_normals" value="true"/>\n'
                   f'{transform}        <ref id="{material}"/>\n{emitter}    </shape>\n')
    xml.append("</scene>\n")
    with open(os.path.join(folder, "scene.xml"), "w") as f:
        f.write("".join(xml))
    triangles = sum(len(meshes[mesh][1]) for _, mesh, _, _ in instances)
    with open(os.path.join(folder, "scene.json"), "w") as f:
        json.dump({"name": name, "description": description, "triangles": triangles,
                   "environment": os.path.relpath(environment, folder) if environment else None}, f, indent=1)
    print(f"{name}: {triangles:,} triangles written to {folder}", file=sys.stderr)


# ---------------------------------------------------------------------------- scenes

def env_mesh(folder):
    armadillo = stand(read_obj(os.path.join(MESHES, "stanford-armadillo-100k.obj"))[0], height=1.0)
    bunny = stand(read_obj(os.path.join(MESHES, "stanford-bunny.obj"))[0], height=0.75)
    meshes = {
        "armadillo": (armadillo, read_obj(os.path.join(MESHES, "stanford-armadillo-100k.obj"))[1]),
        "bunny": (bunny, read_obj(os.path.join(MESHES, "stanford-bunny.obj"))[1]),
        "ground": disk(2.0),
    }
    materials = [lambert("statue", [0.8, 0.75, 0.7]), lambert("ground", [0.4, 0.4, 0.4]),
                 {"name": "metal", "kind": "metal", "roughness": 0.3}]
    instances = [("armadillo", "armadillo", "statue", yaw_translate(180, [-0.5, 0, 0])),
                 ("bunny", "bunny", "metal", yaw_translate(0, [0.55, 0, 0.1])),
                 ("ground", "ground", "ground", np.eye(4))]
    camera = ([0.0, 1.1, 3.2], [0.0, 0.45, 0.0], [0.0, 1.0, 0.0], 32.0)
    write_scene(folder, "env_mesh", "The armadillo (Lambert) and the bunny (rough metal) on a Lambert disk, "
                "lit only by venice_sunset_1k.hdr.", meshes, instances, materials, camera, environment=ENVMAP)


def cornell_box():
    """The walls and light of ../shared/references/cornell_dragon, read from its PLYs: (meshes,
    instances) with materials named white, green, red and light."""
    meshes, instances = {}, []
    for wall, material in (("floor", "white"), ("ceiling", "white"), ("back_wall", "white"),
                           ("right_wall_green", "green"), ("left_wall_red", "red"), ("light", "light")):
        meshes[wall] = read_ply(os.path.join(CORNELL_DRAGON, "meshes", f"{wall}.ply"))
        instances.append((wall, wall, material, np.eye(4)))
    return meshes, instances


def million(folder):
    materials = [lambert("white", [0.885809, 0.698859, 0.666422]), lambert("green", [0.105421, 0.37798, 0.076425]),
                 lambert("red", [0.570068, 0.0430135, 0.0443706]), lambert("grey", [0.5, 0.5, 0.5]),
                 lambert("blue", [0.2, 0.3, 0.6]),
                 {"name": "glass", "kind": "glass"}, {"name": "mirror", "kind": "metal", "roughness": 0.0},
                 {"name": "rough_metal", "kind": "metal", "roughness": 0.3},
                 {"name": "light", "kind": "emitter", "radiance": [18.387, 13.9873, 6.75357]}]
    meshes, instances = cornell_box()
    lucy_v, lucy_f = read_obj(os.path.join(MESHES, "stanford-lucy-100k.obj"))
    armadillo_v, armadillo_f = read_obj(os.path.join(MESHES, "stanford-armadillo-100k.obj"))
    dragon_v, dragon_f = read_ply(os.path.join(MESHES, "stanford-dragon-100k.ply"))
    meshes["lucy"] = (stand(lucy_v, height=260, width=125), lucy_f)
    meshes["armadillo"] = (stand(armadillo_v, height=190, width=125), armadillo_f)
    meshes["dragon"] = (stand(dragon_v, width=140), dragon_f)
    columns = [85, 210, 345, 470]
    rows = (("lucy", 440, 180, ["grey", "rough_metal", "white", "blue"]),
            ("armadillo", 300, 180, ["white", "grey", "mirror", "white"]),
            ("dragon", 150, 200, ["white", "glass", "blue", "grey"]))
    for mesh, z, yaw, row_materials in rows:
        for k, (x, material) in enumerate(zip(columns, row_materials)):
            instances.append((f"{mesh}_{k}", mesh, material, yaw_translate(yaw + 15 * (k - 1.5), [x, 0, z])))
    camera = ([278.0, 273.0, -800.0], [278.0, 273.0, 0.0], [0.0, 1.0, 0.0], 39.30764811610662)
    write_scene(folder, "million", "The Cornell box of cornell_dragon holding twelve statues (four Lucys, four "
                "armadillos, four dragons): one glass, one mirror, one rough metal, the rest Lambert.",
                meshes, instances, materials, camera)


def uv_sphere(centre, radius, rings=48, segments=96):
    """A sphere of `rings` x `segments` quads (poles as triangle fans), outward-facing."""
    vertices = [[0.0, radius, 0.0]]
    for i in range(1, rings):
        theta = math.pi * i / rings
        for j in range(segments):
            phi = 2 * math.pi * j / segments
            vertices.append([radius * math.sin(theta) * math.cos(phi), radius * math.cos(theta), radius * math.sin(theta) * math.sin(phi)])
    vertices.append([0.0, -radius, 0.0])
    ring = lambda i, j: 1 + (i - 1) * segments + j % segments
    faces = [[0, ring(1, j + 1), ring(1, j)] for j in range(segments)]
    for i in range(1, rings - 1):
        for j in range(segments):
            a, b, c, d = ring(i, j), ring(i, j + 1), ring(i + 1, j), ring(i + 1, j + 1)
            faces += [[a, b, d], [a, d, c]]
    bottom = len(vertices) - 1
    faces += [[bottom, ring(rings - 1, j), ring(rings - 1, j + 1)] for j in range(segments)]
    return (np.array(vertices) + np.array(centre)).astype(np.float32), np.array(faces, np.uint32)


def quad(corner, edge_u, edge_v):
    """A parallelogram from `corner` along the two edges, facing edge_u x edge_v."""
    corner, edge_u, edge_v = (np.array(v, float) for v in (corner, edge_u, edge_v))
    vertices = np.array([corner, corner + edge_u, corner + edge_u + edge_v, corner + edge_v], np.float32)
    return vertices, np.array([[0, 1, 2], [0, 2, 3]], np.uint32)


def mirror_caustic(folder):
    materials = [lambert("white", [0.885809, 0.698859, 0.666422]), lambert("green", [0.105421, 0.37798, 0.076425]),
                 lambert("red", [0.570068, 0.0430135, 0.0443706]),
                 {"name": "glass", "kind": "glass"}, {"name": "mirror", "kind": "metal", "roughness": 0.0},
                 {"name": "light", "kind": "emitter", "radiance": [18.387, 13.9873, 6.75357]}]
    meshes, instances = cornell_box()
    # The glass ball focuses the light onto the floor below it; the mirror, hung on the back
    # wall with its top tilted out towards the camera, shows that floor from above.
    meshes["ball"] = uv_sphere([278.0, 190.0, 200.0], 70.0)
    tilt = math.radians(30.0)
    up = [0.0, math.cos(tilt) * 230.0, -math.sin(tilt) * 230.0]
    meshes["mirror"] = quad([90.0, 290.0, 545.0], [376.0, 0.0, 0.0], up)
    instances += [("ball", "ball", "glass", np.eye(4)), ("mirror", "mirror", "mirror", np.eye(4))]
    camera = ([278.0, 273.0, -800.0], [278.0, 273.0, 0.0], [0.0, 1.0, 0.0], 39.30764811610662)
    write_scene(folder, "mirror_caustic", "The Cornell box of cornell_dragon with a glass ball under the light and a "
                "mirror on the back wall, its top tilted out: the ball's caustic on the floor seen directly and in the "
                "mirror (specular-diffuse-specular paths).", meshes, instances, materials, camera)


SCENES = {"env_mesh": env_mesh, "million": million, "mirror_caustic": mirror_caustic}


def ensure(name, out=os.path.join(ROOT, "assets", "suite")):
    """Build scene `name` under `out` unless its four files are there; returns its folder."""
    folder = os.path.join(out, name)
    if not all(os.path.exists(os.path.join(folder, f)) for f in ("scene.gltf", "scene.bin", "scene.xml", "scene.json")):
        SCENES[name](folder)
    return folder


# ---------------------------------------------------------------------------- references

def render_reference(folder, minutes, batch_spp=32):
    """Mitsuba `llvm_ad_rgb` batches of `batch_spp` with seeds 0, 1, ... until `minutes` are
    spent; writes reference.exr (the mean), reference_stderr.exr (the standard error of the
    mean from the batches' spread) as half float, and reference.json (spp, seconds, noise)."""
    os.environ.setdefault("DRJIT_LIBLLVM_PATH", "/usr/lib/x86_64-linux-gnu/libLLVM-19.so")
    import mitsuba as mi
    mi.set_variant("llvm_ad_rgb")
    scene = mi.load_file(os.path.join(folder, "scene.xml"))
    total = total_sq = None
    batches, start = 0, time.perf_counter()
    while time.perf_counter() - start < minutes * 60 or batches < 2:
        image = np.array(mi.render(scene, spp=batch_spp, seed=batches), np.float64)[..., :3]
        total = image if total is None else total + image
        total_sq = image ** 2 if total_sq is None else total_sq + image ** 2
        batches += 1
        print(f"batch {batches}: {batches * batch_spp} spp, {time.perf_counter() - start:.0f} s", file=sys.stderr)
    seconds = time.perf_counter() - start
    mean = total / batches
    variance = np.maximum(total_sq / batches - mean ** 2, 0) * batches / (batches - 1)
    stderr = np.sqrt(variance / batches)
    floor = float(np.mean(stderr ** 2 / (mean ** 2 + 1e-2)))
    for path, array in (("reference.exr", mean), ("reference_stderr.exr", stderr)):
        bitmap = mi.Bitmap(array.astype(np.float32), mi.Bitmap.PixelFormat.RGB)
        bitmap.convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float16, False).write(os.path.join(folder, path))
    meta = {"variant": "llvm_ad_rgb", "mitsuba_version": mi.__version__, "integrator": "path", "max_depth": -1,
            "sampler": "independent", "rfilter": "box", "spp": batches * batch_spp, "batches": batches,
            "spp_per_batch": batch_spp, "seeds": f"0..{batches - 1}", "render_seconds": round(seconds, 1),
            "noise_floor_relmse": floor,
            "noise_note": "expected relMSE (epsilon 1e-2) of this mean against the exact image, from the batch spread"}
    with open(os.path.join(folder, "reference.json"), "w") as f:
        json.dump(meta, f, indent=1)
    print(f"{folder}: {batches * batch_spp} spp in {seconds:.0f} s, own noise relMSE {floor:.2e}", file=sys.stderr)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scenes", default=",".join(SCENES), help="comma-separated: " + ", ".join(SCENES))
    parser.add_argument("--out", default=os.path.join(ROOT, "assets", "suite"))
    parser.add_argument("--force", action="store_true", help="rebuild even where the files exist")
    parser.add_argument("--reference", metavar="SCENE", help="render SCENE's Mitsuba reference")
    parser.add_argument("--minutes", type=float, default=10.0, help="Mitsuba time for --reference")
    args = parser.parse_args()
    if args.reference:
        if args.reference not in SCENES:
            sys.exit(f"--reference {args.reference}: not a suite scene of this script ({', '.join(SCENES)})")
        render_reference(ensure(args.reference, args.out), args.minutes)
        return 0
    for name in args.scenes.split(","):
        if name not in SCENES:
            sys.exit(f"--scenes: unknown scene {name!r} (known: {', '.join(SCENES)})")
        if args.force:
            SCENES[name](os.path.join(args.out, name))
        else:
            ensure(name, args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
