#!/usr/bin/env python3
"""Writes the small test textures of scenes/ (run from anywhere; deterministic):
  checker.tga   32x32 RGB, uncompressed TGA: 4x4 squares of orange and teal,
                a white mark in the top-left square (orientation checks)
  bumps.tga     32x32 tangent-space normal map (RGB = 0.5 * (n + 1)): a grid of
                4x4 hemispherical bumps
  checker.png   the checker as a PNG (glTF tests embed it)
"""
import math, os, struct, zlib

HERE = os.path.dirname(os.path.abspath(__file__))
N = 32

def checker(x, y):
    if x < 4 and y < 4:
        return (255, 255, 255)
    return (230, 120, 30) if ((x // 8) + (y // 8)) % 2 == 0 else (20, 140, 150)

def bump(x, y):
    cx, cy = (x % 8) - 3.5, (y % 8) - 3.5
    r2 = (cx * cx + cy * cy) / 16.0
    if r2 >= 1.0:
        n = (0.0, 0.0, 1.0)
    else:
        # rows go down the image while v goes up: y grows against the bitangent
        n = (cx / 4.0, -cy / 4.0, math.sqrt(1.0 - r2))
    return tuple(int(round(255 * 0.5 * (c + 1.0))) for c in n)

def write_tga(path, texel):
    # type 2 (uncompressed true colour), 24 bits, origin top-left (descriptor bit 5)
    header = struct.pack('<BBBHHBHHHHBB', 0, 0, 2, 0, 0, 0, 0, 0, N, N, 24, 0x20)
    body = bytearray()
    for y in range(N):
        for x in range(N):
            r, g, b = texel(x, y)
            body += bytes((b, g, r))
    with open(path, 'wb') as f:
        f.write(header + bytes(body))

def write_png(path, texel):
    raw = bytearray()
    for y in range(N):
        raw.append(0)
        for x in range(N):
            raw += bytes(texel(x, y))
    def chunk(kind, data):
        c = struct.pack('>I', len(data)) + kind + data
        return c + struct.pack('>I', zlib.crc32(kind + data) & 0xffffffff)
    png = b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', N, N, 8, 2, 0, 0, 0))
    png += chunk(b'IDAT', zlib.compress(bytes(raw), 9)) + chunk(b'IEND', b'')
    with open(path, 'wb') as f:
        f.write(png)

write_tga(os.path.join(HERE, 'checker.tga'), checker)
write_tga(os.path.join(HERE, 'bumps.tga'), bump)
write_png(os.path.join(HERE, 'checker.png'), checker)
