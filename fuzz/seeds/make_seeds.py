"""Writes the small seed inputs for the fuzz targets (run from this folder; python3, no packages).
The fuzzers start from these so that they reach the tracing code, not only the decoders."""
import math, struct, zlib

def strokes(w, h):
    """A cross, a bar and a ring of dark ink on white paper, as rows of gray levels."""
    img = [[235] * w for _ in range(h)]
    def disk(cx, cy, r):
        for y in range(max(0, int(cy - r)), min(h, int(cy + r) + 2)):
            for x in range(max(0, int(cx - r)), min(w, int(cx + r) + 2)):
                if (x + .5 - cx) ** 2 + (y + .5 - cy) ** 2 <= r * r:
                    img[y][x] = 20
    for t in range(200):
        s = t / 199
        disk(6 + s * (w - 12), 6 + s * (h / 2 - 6), 2.5)
        disk(6 + s * (w - 12), h / 2 - s * (h / 2 - 6), 2.5)
        disk(8 + s * (w - 16), h * .65, 2)
        a = s * 2 * math.pi
        disk(w / 2 + w * .15 * math.cos(a), h * .85 + h * .1 * math.sin(a), 1.6)
    return img

def chunk(kind, body):
    return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))

def png(rows, depth=8, color=0, extra=b""):
    h, w = len(rows), len(rows[0])
    raw = b""
    for r in rows:
        if depth == 16:
            raw += b"\0" + b"".join(struct.pack(">H", v * 257) for v in r)
        else:
            raw += b"\0" + bytes(r)
    ihdr = struct.pack(">IIBBBBB", w, h, depth, color, 0, 0, 0)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + extra
            + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))

img = strokes(48, 48)
open("decode_trace/gray8.png", "wb").write(png(img))
open("decode_trace/gray16.png", "wb").write(png(strokes(24, 24), depth=16))
pal = [[0 if v < 128 else 1 for v in r] for r in strokes(32, 32)]
open("decode_trace/palette.png", "wb").write(
    png(pal, color=3, extra=chunk(b"PLTE", bytes([10, 10, 10, 250, 250, 250]))))
open("decode_trace/gray.pgm", "wb").write(b"P5 48 48 255\n" + b"".join(bytes(r) for r in img))
bits = b""
for r in strokes(40, 40):
    row = 0
    out = b""
    for x, v in enumerate(r):
        row = (row << 1) | (v < 128)
        if x % 8 == 7:
            out += bytes([row]); row = 0
    bits += out
open("decode_trace/bits.pbm", "wb").write(b"P4 40 40\n" + bits)

# trace_points: selector byte, then the payload.
text = "".join(f"{10 + i * .5} {20 + (i % 7) * .01}\n" for i in range(60))
text += "".join(f"{30 + 8 * math.cos(i / 8)} {40 + 8 * math.sin(i / 8)}\n" for i in range(50))
open("trace_points/text.txt", "wb").write(b"\0" + text.encode())
open("trace_points/text_paper.txt", "wb").write(b"\4" + text.encode())
raw = b"".join(struct.pack("<dd", 5 + i * 0.7, 5 + i * 0.3) for i in range(40))
raw += b"".join(struct.pack("<dd", 20 - i * 0.5, 5 + i * 0.6) for i in range(40))
open("trace_points/raw.bin", "wb").write(b"\1" + raw)
pairs = bytes(v for i in range(60) for v in (10 + i, 40))
pairs += bytes(v for i in range(60) for v in (40, 10 + i))
pairs += bytes(v for i in range(30) for v in (20 + i, 20 + i))
open("trace_points/bytes.bin", "wb").write(b"\2\4" + pairs)
