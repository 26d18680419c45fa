#!/usr/bin/env python3
"""Image level per region (the material the eye sees), for bench/rb_bias.sh. Python standard library only.

  rb_regions.py labels IN.glb OUT.glb
      writes a copy of the scene in which every material is black and emits a code of its own
      (material k: R = (k + 1) / 16), so a path-traced image of it (--no-light-sampling) labels each
      pixel with the material of its first hit; edge pixels, whose jittered samples mix two codes,
      are left out.
  rb_regions.py levels LABELS.exr LABELS.glb REFERENCE.exr IMAGE.exr...
      prints one JSON object per IMAGE: the relative level (image - reference) / reference over all
      pixels and over the pixels of each material (materials named wall* are pooled as "walls"),
      plus the pixel count of each region.
"""
import json
import struct
import sys
import zlib


def read_glb(path):
    b = open(path, 'rb').read()
    json_length = struct.unpack_from('<I', b, 12)[0]
    return json.loads(b[20:20 + json_length]), b[20 + json_length:]


def write_glb(path, gltf, rest):
    text = json.dumps(gltf).encode()
    text += b' ' * ((4 - len(text) % 4) % 4)
    body = struct.pack('<II', len(text), 0x4E4F534A) + text + rest
    open(path, 'wb').write(struct.pack('<III', 0x46546C67, 2, 12 + len(body)) + body)


def _unpredict(data):  # OpenEXR ZIP: undo the byte delta, then the split into even and odd bytes
    b = bytearray(data)
    for i in range(1, len(b)):
        b[i] = (b[i - 1] + b[i] - 128) & 0xff
    half = (len(b) + 1) // 2
    out = bytearray(len(b))
    out[0::2], out[1::2] = b[:half], b[half:]
    return bytes(out)


def read_exr(path):
    """Scanline OpenEXR (NONE, ZIPS or ZIP; HALF or FLOAT channels) -> (width, height, {channel: [values]})."""
    f = open(path, 'rb').read()
    if struct.unpack_from('<I', f, 0)[0] != 20000630:
        raise ValueError(f'{path}: not an OpenEXR file')
    p, attrs = 8, {}
    while f[p] != 0:
        e = f.index(b'\0', p); name = f[p:e].decode(); p = e + 1
        e = f.index(b'\0', p); p = e + 1
        size = struct.unpack_from('<i', f, p)[0]; p += 4
        attrs[name] = f[p:p + size]; p += size
    p += 1
    channels, q, chl = [], 0, attrs['channels']
    while chl[q] != 0:
        e = chl.index(b'\0', q); name = chl[q:e].decode(); q = e + 1
        channels.append((name, struct.unpack_from('<i', chl, q)[0])); q += 16
    compression = attrs['compression'][0]
    if compression not in (0, 2, 3):
        raise ValueError(f'{path}: compression {compression} not supported')
    x0, y0, x1, y1 = struct.unpack('<4i', attrs['dataWindow'])
    w, h = x1 - x0 + 1, y1 - y0 + 1
    lines = 16 if compression == 3 else 1
    offsets = struct.unpack_from('<%dQ' % ((h + lines - 1) // lines), f, p)
    out = {name: [0.0] * (w * h) for name, _ in channels}
    for o in offsets:
        y, size = struct.unpack_from('<ii', f, o)
        data = f[o + 8:o + 8 + size]
        n = min(lines, y1 + 1 - y)
        if compression != 0 and size < sum(w * (4 if t == 2 else 2) for _, t in channels) * n:
            data = _unpredict(zlib.decompress(data))
        q = 0
        for line in range(n):
            row = (y - y0 + line) * w
            for name, t in channels:
                fmt, step = ('<%df', 4) if t == 2 else ('<%de', 2)
                out[name][row:row + w] = struct.unpack_from(fmt % w, data, q)
                q += step * w
    return w, h, out


def grey(path):
    _, _, c = read_exr(path)
    return [(r + g + b) / 3.0 for r, g, b in zip(c['R'], c['G'], c['B'])]


def labels(src, dst):
    gltf, rest = read_glb(src)
    if len(gltf['materials']) > 15:
        raise ValueError('more than 15 materials')
    for k, m in enumerate(gltf['materials']):
        m.setdefault('extras', {})['phong'] = {'kd': [0, 0, 0], 'ks': [0, 0, 0], 'shininess': 1}
        m['emissiveFactor'] = [(k + 1) / 16.0, 0.0, 0.0]
        m.pop('extensions', None)
        m.pop('pbrMetallicRoughness', None)
    gltf.pop('extensionsUsed', None)
    write_glb(dst, gltf, rest)


def levels(label_exr, label_glb, reference, images):
    gltf, _ = read_glb(label_glb)
    names = [m.get('name', f'material {k}') for k, m in enumerate(gltf['materials'])]
    _, _, c = read_exr(label_exr)
    region = []
    for v in c['R']:
        code = v * 16.0
        k = round(code) - 1
        pure = abs(code - round(code)) < 0.02 and 0 <= k < len(names)
        region.append(('walls' if names[k].startswith('wall') else names[k]) if pure else None)
    ref = grey(reference)
    counts = {}
    for r in region:
        if r is not None:
            counts[r] = counts.get(r, 0) + 1
    for path in images:
        img = grey(path)
        out = {'all': sum(img) / sum(ref) - 1.0}
        for name in counts:
            a = sum(v for v, r in zip(img, region) if r == name)
            b = sum(v for v, r in zip(ref, region) if r == name)
            out[name] = a / b - 1.0 if b > 0 else 0.0
        print(json.dumps({'image': path, 'relative_level': out, 'pixels': counts}))


if __name__ == '__main__':
    if len(sys.argv) == 4 and sys.argv[1] == 'labels':
        labels(sys.argv[2], sys.argv[3])
    elif len(sys.argv) >= 6 and sys.argv[1] == 'levels':
        levels(sys.argv[2], sys.argv[3], sys.argv[4], sys.argv[5:])
    else:
        sys.stderr.write(__doc__)
        sys.exit(2)
