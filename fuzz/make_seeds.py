#!/usr/bin/env python3
"""Writes the hand-made seed inputs of fuzz/corpus/ (run from anywhere).

The seeds are committed; this script documents how each was made and
regenerates them.  Seeds are small valid (or nearly valid) inputs that reach
deep into each parser quickly: the fuzzer mutates from there.  The .kdt seed
is made with `rtt bake` instead (see README.md)."""
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))


def write(harness, name, data):
    path = os.path.join(HERE, "corpus", harness, name)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode())


# --- assimp: first byte picks obj/ply/off/stl/gltf (index mod 5) -----------
OBJ = """# unit cube, quads and a triangle, one normal set
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0 0 1
v 1 0 1
v 1 1 1
v 0 1 1
vn 0 0 -1
f 1//1 2//1 3//1 4//1
f 5 6 7 8
f 1 2 6 5
f 2 3 7
"""
PLY = """ply
format ascii 1.0
element vertex 4
property float x
property float y
property float z
element face 2
property list uchar int vertex_indices
end_header
0 0 0
1 0 0
1 1 0
0 1 0
3 0 1 2
4 0 1 2 3
"""
OFF = """OFF
4 2 0
0 0 0
1 0 0
0 1 0
0 0 1
3 0 1 2
3 0 2 3
"""
STL = """solid t
facet normal 0 0 1
 outer loop
  vertex 0 0 0
  vertex 1 0 0
  vertex 0 1 0
 endloop
endfacet
endsolid t
"""


def gltf():
    import base64
    positions = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
    indices = struct.pack("<3H", 0, 1, 2) + b"\0\0"
    blob = positions + indices
    uri = "data:application/octet-stream;base64," + base64.b64encode(blob).decode()
    return ('{"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],'
            '"meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}],'
            '"buffers":[{"byteLength":%d,"uri":"%s"}],'
            '"bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36},'
            '{"buffer":0,"byteOffset":36,"byteLength":6}],'
            '"accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3",'
            '"min":[0,0,0],"max":[1,1,0]},'
            '{"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}]}' % (len(blob), uri))


for index, (name, text) in enumerate([("cube.obj", OBJ), ("quad.ply", PLY), ("tet.off", OFF),
                                      ("tri.stl", STL), ("tri.gltf", gltf())]):
    write("assimp", name, bytes([index]) + text.encode())


# --- q3bsp: IBSP 46 with one polygon face, one mesh face, one 3x3 patch -----
def ibsp():
    lumps = [b""] * 17
    lumps[1] = struct.pack("<64sii", b"textures/base/floor", 0, 1)          # texture
    verts = []
    def vert(x, y, z):
        return struct.pack("<3f2f2f3f4B", x, y, z, 0, 0, 0, 0, 0, 0, 1, 255, 255, 255, 255)
    quad = [(0, 0, 0), (64, 0, 0), (64, 64, 0), (0, 64, 0)]
    patch = [(x * 32, y * 32, (16 if (x == 1 and y == 1) else 0) + 32) for y in range(3) for x in range(3)]
    for p in quad + patch:
        verts.append(vert(*p))
    lumps[10] = b"".join(verts)                                              # drawVerts
    lumps[11] = struct.pack("<6i", 0, 1, 2, 0, 2, 3)                           # meshVerts
    def face(kind, first_vertex, n_vertexes, first_meshvert, n_meshverts, size=(0, 0)):
        return struct.pack("<12i12f2i", 0, -1, kind, first_vertex, n_vertexes, first_meshvert, n_meshverts,
                           -1, 0, 0, 0, 0, *([0.0] * 9), 0, 0, 1, *size)
    faces = [face(1, 0, 4, 0, 6), face(3, 0, 4, 0, 6), face(2, 4, 9, 0, 0, (3, 3))]
    lumps[13] = b"".join(faces)                                              # faces
    lumps[7] = struct.pack("<6f4i", 0, 0, 0, 64, 64, 64, 0, len(faces), 0, 0)  # models: world
    header_size = 8 + 17 * 8
    offset = header_size
    directory = b""
    body = b""
    for lump in lumps:
        directory += struct.pack("<ii", offset, len(lump))
        body += lump
        offset += len(lump)
    return b"IBSP" + struct.pack("<i", 46) + directory + body


write("q3bsp", "three_faces.bsp", ibsp())


# --- kd_build: see the layout comment in fuzz_kd_build.c ------------------------
def kd_input(triangles, header, rays=b""):
    out = bytes(header)
    for tri in triangles:
        for v in tri:
            if isinstance(v, int):
                out += bytes([v])                      # repeat vertex v (< 48)
            else:
                out += bytes([0xFF]) + bytes(v)        # three palette bytes
    return out + rays


def p(n):  # palette byte of the integer n in -16..16
    return 16 + 16 + n


cube = []
corners = [(p(x), p(y), p(z)) for x in (0, 1) for y in (0, 1) for z in (0, 1)]
for a, b, c in [(0, 1, 3), (0, 3, 2), (4, 6, 7), (4, 7, 5), (0, 4, 5), (0, 5, 1),
                (2, 3, 7), (2, 7, 6), (0, 2, 6), (0, 6, 4), (1, 5, 7), (1, 7, 3)]:
    cube.append([corners[a], corners[b], corners[c]])
eye = bytes([p(3), p(2), p(5)])
vertex_rays = b"".join(bytes([0, p(3), p(2), p(5), k]) for k in range(8))        # at vertices
edge_rays = b"".join(bytes([1, p(-2), p(1), p(3), k, k + 1, 128]) for k in range(6))
axis_rays = b"".join(bytes([2, p(0), p(0), p(-3), b]) for b in (2, 2 | 8, 2 | 8 | 16, 66))
write("kd_build", "cube_rays", kd_input(cube, [len(cube) - 1, 0, 0, 0, 3], eye + vertex_rays + edge_rays + axis_rays))
write("kd_build", "cube_far_huge", kd_input(cube, [len(cube) - 1, 2 << 1, 2, 5, 0], eye + vertex_rays))
write("kd_build", "cube_far", kd_input(cube, [len(cube) - 1, 0, 3, 0, 2], eye + vertex_rays + axis_rays))
write("kd_build", "cube_tiny", kd_input(cube, [len(cube) - 1, 1 << 1, 0, 1, 1], eye + edge_rays))
# flags bit 4: the cube's corners welded, a solid (back faces culled by pgrid and bvh-mft's camera path)
write("kd_build", "cube_solid_rays", kd_input(cube, [len(cube) - 1, 0, 0, 0, 16 | 3], eye + vertex_rays + edge_rays))
write("kd_build", "cube_solid_far", kd_input(cube, [len(cube) - 1, 0, 3, 0, 16], eye + vertex_rays + axis_rays))
degenerate = [[(p(0), p(0), p(0)), (p(1), p(0), p(0)), (p(2), p(0), p(0))],   # collinear
              [(p(0), p(0), p(0)), 0, 0],                                     # a point
              [(p(0), p(0), p(0)), (p(1), p(0), p(0)), (p(0), p(1), p(0))],   # duplicate pair
              [(p(0), p(0), p(0)), (p(1), p(0), p(0)), (p(0), p(1), p(0))],
              [(8, 8, 8), (9, 9, 9), (p(0), p(1), p(0))]]                     # denormal, FLT_MIN
write("kd_build", "degenerate", kd_input(degenerate, [len(degenerate) - 1, 0, 0, 0, 0], eye + vertex_rays))
nan = struct.pack("<f", float("nan"))
raw = bytes([0, 1, 0, 0, 0]) + (bytes([0xFF]) + nan + struct.pack("<2f", 0, 0)) + bytes([0xFF]) + struct.pack("<3f", 1, 0, 0) + bytes([0xFF]) + struct.pack("<3f", 0, 1, 0)
write("kd_build", "raw_nan", raw)

# --- pgrid: see the layout comment in fuzz_pgrid.c ----------------------------
floor = [[(p(-4), p(-1), p(-4)), (p(4), p(-1), p(-4)), (p(4), p(-1), p(4))],
         [(p(-4), p(-1), p(-4)), (p(4), p(-1), p(4)), (p(-4), p(-1), p(4))]]
light = bytes([3, p(2), p(6), p(3)])                                            # a palette point
on_floor = b"".join(bytes([1, 12 + k % 2, 40 * k % 256, 90 * k % 256]) for k in range(12))  # surface points
on_cube = b"".join(bytes([1, k, 128, 64]) for k in range(12)) + b"".join(bytes([0, k]) for k in range(8))
write("pgrid", "cube_floor", kd_input(cube + floor, [len(cube) + 1, 0, 0, 6], light + on_floor + on_cube))
write("pgrid", "cube_floor_coarse", kd_input(cube + floor, [len(cube) + 1, 0, 1, 1], light + on_floor + on_cube))
write("pgrid", "light_on_a_vertex", kd_input(cube + floor, [len(cube) + 1, 0, 0, 4], bytes([0, 3]) + on_floor + on_cube))
write("pgrid", "far_huge", kd_input(cube + floor, [len(cube) + 1, 2 << 1, 2, 6], light + on_floor + on_cube))
write("pgrid", "tiny", kd_input(cube + floor, [len(cube) + 1, 1 << 1, 0, 5], bytes([2, 1, 6]) + on_floor + on_cube))
# the soft grid's sphere light (mode bits 4-5: radius 0.05, 1 or 20 times the scale; bits 6-7: 1, 3, 5 or 7 slices)
write("pgrid", "soft_small_light", kd_input(cube + floor, [len(cube) + 1, 1 << 4 | 1 << 6, 0, 6], light + on_floor + on_cube))
write("pgrid", "soft_large_light", kd_input(cube + floor, [len(cube) + 1, 2 << 4 | 3 << 6, 0, 4], light + on_floor + on_cube))
write("pgrid", "soft_light_around_the_scene", kd_input(cube + floor, [len(cube) + 1, 3 << 4 | 2 << 6, 0, 3], light + on_floor + on_cube))
write("pgrid", "soft_on_a_vertex", kd_input(cube + floor, [len(cube) + 1, 1 << 4 | 1 << 6, 0, 5], bytes([0, 3]) + on_floor + on_cube))


# --- kdt: mutations of a baked file -----------------------------------------
# tri.kdt, box.kdt and thin_plate.kdt are made with `rtt bake` (README.md):
# a one-triangle inline mesh, a box with a sphere light and a reflective
# material, and scenes/shadow_thin_plate.json.  The harness repairs the
# checksum of what it loads, so these reach the checks behind it.
def kdt_mutations():
    path = os.path.join(HERE, "corpus", "kdt", "tri.kdt")
    if not os.path.exists(path):
        return
    with open(path, "rb") as f:
        baked = bytearray(f.read())
    write("kdt", "tri_truncated.kdt", bytes(baked[:600]))
    more_nodes = bytearray(baked)                    # node_count at offset 60
    struct.pack_into("<I", more_nodes, 60, struct.unpack_from("<I", baked, 60)[0] + 1000)
    write("kdt", "tri_node_count_past_end.kdt", bytes(more_nodes))
    huge = bytearray(baked)                          # triangle_count at offset 44
    struct.pack_into("<I", huge, 44, 0xFFFFFFFF)
    write("kdt", "tri_triangle_count_huge.kdt", bytes(huge))


kdt_mutations()


# --- pk3: zip archives, stored and deflated members, a script and an image --
def pk3_seeds():
    import io
    import zipfile
    shader = ("textures/seed/wall\n{\n\t{\n\t\tmap $lightmap\n\t}\n\t{\n\t\tmap textures/seed/wall.tga\n"
              "\t\tblendFunc filter\n\t}\n}\n")
    tga = struct.pack("<BBBHHBHHHHBB", 0, 0, 2, 0, 0, 0, 0, 0, 2, 2, 24, 0x20) + bytes(range(12))
    for name, method in (("stored.pk3", zipfile.ZIP_STORED), ("deflated.pk3", zipfile.ZIP_DEFLATED)):
        out = io.BytesIO()
        with zipfile.ZipFile(out, "w", method) as z:
            for member, data in (("scripts/seed.shader", shader), ("textures/seed/wall.tga", tga)):
                info = zipfile.ZipInfo(member, date_time=(2008, 1, 1, 0, 0, 0))  # fixed: reproducible bytes
                info.compress_type = method
                z.writestr(info, data)
        write("pk3", name, out.getvalue())


pk3_seeds()

# --- q3_shader: scripts with comments, quoted names, animMap, clampMap ------
write("q3_shader", "stages.shader",
      "// a comment\ntextures/a/b\n{\n\tqer_editorimage textures/a/b.tga\n\tsurfaceparm nomarks\n"
      "\t{\n\t\tmap $lightmap\n\t\trgbGen identity\n\t}\n\t{\n\t\tclampMap textures/a/b.jpg\n"
      "\t\tblendFunc GL_DST_COLOR GL_ZERO\n\t}\n}\n\n"
      "/* block\n comment */ \"textures/quoted name\" { { animMap 8 textures/f1.tga textures/f2.tga } }\n"
      "textures/sky { skyParms full 512 - { map textures/skies/clouds.tga tcMod scroll 0.1 0.1 } }\n")
write("q3_shader", "unclosed.shader", "textures/x\n{\n\t{\n\t\tmap textures/x.tga\n")

# --- texture: the formats stb_image decodes for rtt (TGA, PNG) ---------------
def texture_seeds():
    import zlib
    tga = struct.pack("<BBBHHBHHHHBB", 0, 0, 2, 0, 0, 0, 0, 0, 3, 2, 24, 0x20) + bytes(range(18))
    write("texture", "rgb_3x2.tga", tga)
    rle = struct.pack("<BBBHHBHHHHBB", 0, 0, 10, 0, 0, 0, 0, 0, 4, 1, 24, 0) + bytes([0x83, 10, 20, 30])
    write("texture", "rle_4x1.tga", rle)
    rows = b"\x00" + bytes((0, 0, 0, 255, 255, 255)) + b"\x00" + bytes((255, 0, 0, 0, 0, 255))
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)
    png = (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", 2, 2, 8, 2, 0, 0, 0)) +
           chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))
    write("texture", "rgb_2x2.png", png)


texture_seeds()
