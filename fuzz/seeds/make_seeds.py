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

# Inputs people have: white ink on transparent (RGBA PNG), multi-page TIFFs (classic and BigTIFF),
# JPEG-compressed TIFF pages with a Predictor tag, in gray and in YCbCr.
clear = strokes(40, 40)
raw = b"".join(b"\0" + bytes(c for v in r for c in ((255,) * 4 if v < 128 else (0,) * 4))
              for r in clear)
open("decode_trace/white_on_clear.png", "wb").write(
    b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", 40, 40, 8, 6, 0, 0, 0))
    + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))

def tiff(pages, big=False):
    """A little-endian TIFF of pages, each (entries, strip): entries are (tag, type, values)."""
    word, size = (8, 20) if big else (4, 12)
    num = (lambda v: struct.pack("<Q", v)) if big else (lambda v: struct.pack("<I", v))
    out = bytearray(b"II+\0\x08\0\0\0" + num(0) if big else b"II*\0" + num(0))
    pointer = 8 if big else 4
    fmt = {3: "<H", 4: "<I", 16: "<Q"}
    for entries, strip in pages:
        at = len(out)
        out += strip
        entries = entries + [(273, 16 if big else 4, [at]), (279, 16 if big else 4, [len(strip)])]
        fields = []
        for tag, kind, values in sorted(entries):
            value = b"".join(struct.pack(fmt[kind], v) for v in values)
            if len(value) > word:
                out += b"\0" * (len(out) % 2)
                fields.append((tag, kind, len(values), num(len(out))))
                out += value
            else:
                fields.append((tag, kind, len(values), value.ljust(word, b"\0")))
        out += b"\0" * (len(out) % 2)
        out[pointer:pointer + word] = num(len(out))
        out += struct.pack("<Q" if big else "<H", len(fields))
        for tag, kind, count, value in fields:
            out += struct.pack("<HH", tag, kind) + num(count) + value
        pointer = len(out)
        out += num(0)
    return bytes(out)

def tiff_page(rows, samples=1, photometric=1, compression=1, extra=()):
    h, w = len(rows), len(rows[0]) // samples
    return ([(256, 4, [w]), (257, 4, [h]), (258, 3, [8] * samples), (259, 3, [compression]),
             (262, 3, [photometric]), (277, 3, [samples]), (278, 4, [h])] + list(extra))

def flat(rows):
    return b"".join(bytes(r) for r in rows)

small = strokes(32, 32)
colour = [[c for v in r for c in ((20, 30, 140) if v < 128 else (250, 240, 200))] for r in strokes(24, 24)]
pages = [(tiff_page(small), flat(small)), (tiff_page(colour, 3, 2), flat(colour)),
         (tiff_page(small, extra=[(317, 3, [2])]), flat(small))]
open("decode_trace/pages.tif", "wb").write(tiff(pages))
open("decode_trace/pages_big.tif", "wb").write(tiff(pages[:2], big=True))

def jpeg(planes):
    """A baseline JPEG whose 8x8 blocks are flat (DC only): planes are rows of levels, one plane
    per component, sides multiples of 8; the standard luminance DC table, one AC code (EOB)."""
    h, w = len(planes[0]), len(planes[0][0])
    quant = bytes([1] * 64)
    dc_counts = [0, 1, 5, 1, 1, 1, 1, 1, 1, 0, 0, 0, 0, 0, 0, 0]
    dc_codes, code, k = {}, 0, 0
    for length, n in enumerate(dc_counts, 1):
        for _ in range(n):
            dc_codes[k] = (code, length); code += 1; k += 1
        code <<= 1
    def segment(marker, body):
        return bytes([0xFF, marker]) + struct.pack(">H", len(body) + 2) + body
    n = len(planes)
    out = b"\xff\xd8" + segment(0xDB, b"\0" + quant)
    out += segment(0xC0, struct.pack(">BHHB", 8, h, w, n)
                   + b"".join(bytes([i + 1, 0x11, 0]) for i in range(n)))
    out += segment(0xC4, b"\x00" + bytes(dc_counts) + bytes(range(12)))
    out += segment(0xC4, b"\x10" + bytes([1] + [0] * 15) + b"\x00")  # AC: one 1-bit code, EOB
    out += segment(0xDA, bytes([n]) + b"".join(bytes([i + 1, 0x00]) for i in range(n)) + b"\0\x3f\0")
    bits, nbits, data = 0, 0, bytearray()
    def put(value, length):
        nonlocal bits, nbits
        for i in reversed(range(length)):
            bits = (bits << 1) | ((value >> i) & 1); nbits += 1
            if nbits == 8:
                data.append(bits)
                if bits == 0xFF:
                    data.append(0)
                bits, nbits = 0, 0
    last = [0] * n
    for by in range(0, h, 8):
        for bx in range(0, w, 8):
            for c, plane in enumerate(planes):
                level = plane[by][bx]
                dc = (level - 128) * 8  # the DC of a flat block is 8 x (level - 128)
                diff, last[c] = dc - last[c], dc
                size = abs(diff).bit_length()
                put(*dc_codes[size])
                put(diff if diff >= 0 else diff + (1 << size) - 1, size)
                put(0, 1)  # EOB
    if nbits:
        put((1 << (8 - nbits)) - 1, 8 - nbits)
    return out + bytes(data) + b"\xff\xd9"

# Ink where a block's mean is dark, so that the flat blocks still draw strokes.
gray = strokes(64, 64)
gray = [[20 if sum(gray[(y // 8) * 8 + j][(x // 8) * 8 + i] for j in range(8) for i in range(8))
         < 64 * 215 else 235 for x in range(64)] for y in range(64)]
ycbcr = [gray, [[110 if v < 128 else 120 for v in r] for r in gray],
         [[120 if v < 128 else 135 for v in r] for r in gray]]
open("decode_trace/flat.jpg", "wb").write(jpeg([gray]))
open("decode_trace/jpeg_predictor.tif", "wb").write(
    tiff([(tiff_page(gray, compression=7, extra=[(317, 3, [2])]), jpeg([gray]))]))
open("decode_trace/jpeg_ycbcr.tif", "wb").write(
    tiff([(tiff_page([[0] * 192] * 64, 3, 6, 7, extra=[(317, 3, [2])]), jpeg(ycbcr))]))

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
