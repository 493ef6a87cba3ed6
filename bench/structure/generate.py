# Differential test inputs for the structure validator (issue 14), made from a fixed seed so that
# the agreement figure can be rerun:
#   python3 generate.py WORK SHARED [--count N] [--seed S]
# writes N inputs under WORK (never under SHARED) and their paths to WORK/list.txt. Three sources,
# each mutated one to three times per input:
#   - a synthetic document built here that uses every core object type (buffers and images as data
#     URIs, morph targets, skins, animations of every path and interpolation, both cameras);
#   - copies of the small shared assets (Box, BoxTextured, RiggedSimple, ...) next to their resources;
#   - the Khronos suite's .gltf cases.
# Mutations are typed by the value they touch: an integer becomes another index, a negative, a
# fraction, a string, or the same value written as 1.0 or 1e0; numbers go out of range; enums get
# neighbours' values; arrays lose, gain or repeat elements; objects lose required members or gain
# unknown ones, non-object extras, and extension objects of every extension the suite uses (added to
# extensionsUsed or not). A share of the synthetic documents is written as GLB, some with a broken
# container (cut short, wrong lengths, chunk types, padding).
import argparse, base64, copy, glob, json, math, os, random, shutil, struct, zlib

parser = argparse.ArgumentParser()
parser.add_argument('work')
parser.add_argument('shared')
parser.add_argument('--count', type=int, default=10000)
parser.add_argument('--seed', type=int, default=14)
args = parser.parse_args()
rng = random.Random(args.seed)


class Num:
    """A number written in a chosen form: 1, 1.0 or 1e0 (JSON allows all three for one value)."""
    def __init__(self, text): self.text = text


def dumps(node):
    if isinstance(node, Num): return node.text
    if isinstance(node, dict): return '{' + ','.join(json.dumps(k) + ':' + dumps(v) for k, v in node.items()) + '}'
    if isinstance(node, list): return '[' + ','.join(dumps(v) for v in node) + ']'
    if isinstance(node, float) and (math.isnan(node) or math.isinf(node)): return '1e400'
    return json.dumps(node)


def data_uri(data, mime='application/octet-stream'):
    return 'data:%s;base64,%s' % (mime, base64.b64encode(data).decode())


def png(width, height, rgba):
    rows = b''.join(b'\0' + bytes(rgba) * width for _ in range(height))
    def chunk(kind, body): return struct.pack('>I', len(body)) + kind + body + struct.pack('>I', zlib.crc32(kind + body))
    return (b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', width, height, 8, 6, 0, 0, 0)) +
            chunk(b'IDAT', zlib.compress(rows)) + chunk(b'IEND', b''))


def synthetic():
    """A valid document with every core object type; the binary lives in one buffer."""
    blob = bytearray()
    views, accessors = [], []
    def add(fmt, values, component, kind, count, target=None, minmax=False, normalized=False):
        while len(blob) % 4: blob.append(0)
        offset = len(blob)
        blob.extend(struct.pack('<' + fmt * len(values), *values))
        view = {'buffer': 0, 'byteOffset': offset, 'byteLength': len(blob) - offset}
        if target: view['target'] = target
        views.append(view)
        accessor = {'bufferView': len(views) - 1, 'componentType': component, 'count': count, 'type': kind}
        if normalized: accessor['normalized'] = True
        if minmax:
            width = len(values) // count
            accessor['min'] = [min(values[i::width]) for i in range(width)]
            accessor['max'] = [max(values[i::width]) for i in range(width)]
        accessors.append(accessor)
        return len(accessors) - 1
    positions = [0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0]
    pos = add('f', positions, 5126, 'VEC3', 4, 34962, True)
    nrm = add('f', [0, 0, 1] * 4, 5126, 'VEC3', 4, 34962)
    tan = add('f', [1, 0, 0, 1] * 4, 5126, 'VEC4', 4, 34962)
    uv = add('f', [0, 0, 1, 0, 0, 1, 1, 1], 5126, 'VEC2', 4, 34962)
    col = add('B', [255] * 16, 5121, 'VEC4', 4, 34962, normalized=True)
    jnt = add('B', [0, 1, 0, 0] * 4, 5121, 'VEC4', 4, 34962)
    wgt = add('f', [0.5, 0.5, 0, 0] * 4, 5126, 'VEC4', 4, 34962)
    idx = add('H', [0, 1, 2, 2, 1, 3], 5123, 'SCALAR', 6, 34963)
    mpos = add('f', [0, 0, 0.1] * 4, 5126, 'VEC3', 4, 34962, True)
    mtan = add('f', [0, 0.1, 0] * 4, 5126, 'VEC3', 4, 34962)
    ibm = add('f', [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1] * 2, 5126, 'MAT4', 2)
    times = add('f', [0, 1], 5126, 'SCALAR', 2, minmax=True)
    times3 = add('f', [0, 0.5, 1], 5126, 'SCALAR', 3, minmax=True)
    translations = add('f', [0, 0, 0, 1, 0, 0], 5126, 'VEC3', 2)
    rotations = add('f', [0, 0, 0, 1, 0, 0, 0.70710677, 0.70710677], 5126, 'VEC4', 2)
    cubic = add('f', [0, 0, 0] * 9, 5126, 'VEC3', 9)
    weights = add('f', [0, 1], 5126, 'SCALAR', 2)
    image = png(2, 2, (200, 100, 50, 255))
    doc = {
        'asset': {'version': '2.0', 'generator': 'gltf-pbr differential generator'},
        'scene': 0,
        'scenes': [{'nodes': [0, 1, 3]}],
        'nodes': [
            {'children': [2], 'name': 'root'},
            {'mesh': 0, 'skin': 0, 'name': 'skinned'},
            {'translation': [0, 1, 0], 'children': [4]},
            {'camera': 0, 'rotation': [0, 0, 0, 1], 'scale': [1, 1, 1]},
            {'mesh': 1, 'matrix': [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1], 'weights': [0.5]},
        ],
        'meshes': [
            {'primitives': [{'attributes': {'POSITION': pos, 'NORMAL': nrm, 'TANGENT': tan, 'TEXCOORD_0': uv,
                                            'COLOR_0': col, 'JOINTS_0': jnt, 'WEIGHTS_0': wgt},
                             'indices': idx, 'material': 0, 'mode': 4}]},
            {'primitives': [{'attributes': {'POSITION': pos, 'NORMAL': nrm, 'TANGENT': tan},
                             'targets': [{'POSITION': mpos, 'TANGENT': mtan}], 'material': 1}],
             'weights': [0]},
        ],
        'skins': [{'joints': [2, 4], 'inverseBindMatrices': ibm, 'skeleton': 2}],
        'materials': [
            {'pbrMetallicRoughness': {'baseColorFactor': [1, 1, 1, 1], 'baseColorTexture': {'index': 0},
                                      'metallicFactor': 0.5, 'roughnessFactor': 0.5,
                                      'metallicRoughnessTexture': {'index': 0, 'texCoord': 0}},
             'normalTexture': {'index': 0, 'scale': 1}, 'occlusionTexture': {'index': 0, 'strength': 1},
             'emissiveTexture': {'index': 0}, 'emissiveFactor': [0, 0, 0], 'alphaMode': 'MASK',
             'alphaCutoff': 0.5, 'doubleSided': True},
            {'alphaMode': 'BLEND'},
        ],
        'textures': [{'source': 0, 'sampler': 0}],
        'images': [{'uri': data_uri(image, 'image/png'), 'mimeType': 'image/png'}],
        'samplers': [{'magFilter': 9729, 'minFilter': 9987, 'wrapS': 10497, 'wrapT': 33648}],
        'cameras': [{'type': 'perspective', 'perspective': {'yfov': 0.8, 'znear': 0.1, 'zfar': 100, 'aspectRatio': 1.5}},
                    {'type': 'orthographic', 'orthographic': {'xmag': 1, 'ymag': 1, 'znear': 0, 'zfar': 10}}],
        'animations': [{
            'samplers': [{'input': times, 'output': translations, 'interpolation': 'LINEAR'},
                         {'input': times, 'output': rotations, 'interpolation': 'STEP'},
                         {'input': times3, 'output': cubic, 'interpolation': 'CUBICSPLINE'},
                         {'input': times, 'output': weights}],
            'channels': [{'sampler': 0, 'target': {'node': 2, 'path': 'translation'}},
                         {'sampler': 1, 'target': {'node': 2, 'path': 'rotation'}},
                         {'sampler': 2, 'target': {'node': 3, 'path': 'scale'}},
                         {'sampler': 3, 'target': {'node': 4, 'path': 'weights'}}]}],
        'accessors': accessors,
        'bufferViews': views,
        'buffers': [{'byteLength': len(blob), 'uri': data_uri(bytes(blob))}],
    }
    return doc, bytes(blob)


def walk(node, path=()):
    if isinstance(node, dict):
        for k, v in node.items():
            yield path + (k,), v
            yield from walk(v, path + (k,))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield path + (i,), v
            yield from walk(v, path + (i,))


def harvest_extensions(files):
    """(parent member, extension name) -> extension objects seen in the suite."""
    found = {}
    for f in files:
        try: doc = json.load(open(f))
        except Exception: continue
        for path, value in walk(doc):
            if path and path[-1] == 'extensions' and isinstance(value, dict):
                parent = next((p for p in reversed(path[:-1]) if isinstance(p, str)), 'root')
                for name, body in value.items():
                    if not name.startswith('KHR_invalid'):
                        found.setdefault((parent, name), []).append(body)
    return found


ENUM_STRINGS = ['', 'SCALAR', 'VEC2', 'VEC3', 'VEC4', 'MAT2', 'MAT3', 'MAT4', 'OPAQUE', 'MASK', 'BLEND',
                'translation', 'rotation', 'scale', 'weights', 'pointer', 'LINEAR', 'STEP', 'CUBICSPLINE',
                'perspective', 'orthographic', 'image/png', 'image/jpeg', 'image/webp', 'image/ktx2', '2.0',
                '2.1', '1.0', '3.0', 'POSITION', 'NORMAL', 'TEXCOORD_0', '_CUSTOM', 'JOINTS_0', 'spot', 'point']
GL_VALUES = [0, 1, 4, 5, 6, 5120, 5121, 5122, 5123, 5125, 5126, 5124, 34962, 34963, 9728, 9729, 9984, 9987,
             10497, 33071, 33648]


def int_forms(value):
    return [Num('%d.0' % value), Num('%de0' % value), Num('%dE+0' % value)]


def mutate_value(value, doc):
    """A replacement for one leaf or container, chosen by the kind of value it is."""
    if isinstance(value, bool):
        return rng.choice([not value, 0, 1, 'true', None])
    if isinstance(value, int):
        # 2^53 + 2: beyond the doubles' exact integers, yet representable in one (2^53 + 1 is not,
        # and the npm build, compiled to JavaScript, would read it as 2^53).
        choices = [value + 1, value - 1, value + rng.choice([2, 5, 100]), -1, 0, 2 ** 32, 2 ** 53 + 2, 0.5,
                   str(value), None, [value], rng.choice(GL_VALUES)]
        return rng.choice(choices + int_forms(value) * 2)
    if isinstance(value, float):
        return rng.choice([0, -value, value * 1000, -1, 1.5, 1e-40, 1e40, float('inf'), 'x', None, Num('%r' % value),
                           Num('%.17e' % value), 2, math.pi])
    if isinstance(value, str):
        if value.startswith('data:'):
            head, _, payload = value.partition(',')
            return rng.choice([head + ',' + payload[:-3], head + ',' + payload + '=', head.replace('base64', 'base32') + ',' + payload,
                               'data:application/gltf-buffer;base64,' + payload, 'data:image/jpeg;base64,' + payload,
                               'data:;base64,' + payload, head + ',!' + payload[1:]])
        return rng.choice(ENUM_STRINGS + [value + 'x', value.lower(), 'not_found.bin', 'a b.png', 'a%20b.png',
                                          '../outside.bin', '/abs/file.bin', 'http://example.com/x.bin', 1])
    if isinstance(value, list):
        if not value: return rng.choice([[0], [None], [{}], 'x'])
        kind = rng.randrange(6)
        v = copy.deepcopy(value)
        if kind == 0: return []
        if kind == 1: v.append(copy.deepcopy(v[0])); return v
        if kind == 2: v.pop(); return v
        if kind == 3: v.insert(0, rng.choice([None, 'x', -1, 1.5, {}, []])); return v
        if kind == 4 and all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in v):
            return [Num(('%d.0' if isinstance(x, int) else '%r') % x) for x in v]
        return {'0': v}
    if isinstance(value, dict):
        v = copy.deepcopy(value)
        kind = rng.randrange(5)
        if kind == 0 and v: del v[rng.choice(list(v))]; return v
        if kind == 1: v[rng.choice(['foo', 'name', 'extras', 'extensions', 'byteStride', 'index', 'uri'])] = rng.choice([1, 'x', {}, [], None]); return v
        if kind == 2: v['extras'] = rng.choice([1, 'x', [], {'a': 1}, None]); return v
        if kind == 3: v['extensions'] = rng.choice([1, {}, {'EXT_unknown': {}}, {'KHR_texture_transform': {'offset': [0, 0]}}]); return v
        return rng.choice([None, [], 'x', {}])
    return rng.choice([0, 'x', {}, []])


def add_extension(doc, extensions):
    """Puts an extension object the suite used (or a broken copy) where it belongs, declared or not."""
    (parent, name), bodies = rng.choice(sorted(extensions.items()))
    body = copy.deepcopy(rng.choice(bodies))
    if rng.random() < 0.4: body = mutate_value(body, doc)
    holders = [v for p, v in walk(doc) if p and isinstance(v, dict) and
               (p[-1] == parent or (len(p) > 1 and p[-2] == parent and isinstance(p[-1], int)))]
    if parent == 'root': holders = [doc]
    if not holders: return
    holder = rng.choice(holders)
    if not isinstance(holder.get('extensions'), dict): holder['extensions'] = {}
    holder['extensions'][name] = body
    choice = rng.random()
    if choice < 0.75:
        used = doc.setdefault('extensionsUsed', [])
        if isinstance(used, list) and name not in used: used.append(name)
    if choice < 0.1:
        doc.setdefault('extensionsRequired', []).append(name)


def mutate(doc, extensions):
    paths = [p for p, _ in walk(doc)]
    kind = rng.random()
    if kind < 0.15 and extensions:
        add_extension(doc, extensions)
        return
    if kind < 0.25:
        # Every integer of one object type written as 1.0 or 1e0.
        top = rng.choice([k for k in doc if isinstance(doc[k], (list, dict))] or ['asset'])
        form = rng.choice(['%d.0', '%de0'])
        for p, v in list(walk(doc.get(top))):
            if isinstance(v, int) and not isinstance(v, bool) and rng.random() < 0.5:
                cur = doc[top]
                for q in p[:-1]: cur = cur[q]
                cur[p[-1]] = Num(form % v)
        return
    if not paths: return
    path = rng.choice(paths)
    parent = doc
    for q in path[:-1]: parent = parent[q]
    if isinstance(parent, Num) or not isinstance(parent, (dict, list)): return
    value = parent[path[-1]]
    if rng.random() < 0.2 and isinstance(parent, dict):
        del parent[path[-1]]
    else:
        parent[path[-1]] = mutate_value(value, doc)


def glb(json_text, blob, broken):
    text = json_text.encode()
    text += b' ' * (-len(text) % 4)
    body = blob + b'\0' * (-len(blob) % 4) if blob is not None else b''
    chunks = struct.pack('<I4s', len(text), b'JSON') + text
    if blob is not None: chunks += struct.pack('<I4s', len(body), b'BIN\0') + body
    data = bytearray(struct.pack('<4sII', b'glTF', 2, 12 + len(chunks)) + chunks)
    if broken == 'short': data = data[:rng.randrange(1, len(data))]
    elif broken == 'length': struct.pack_into('<I', data, 8, len(data) + rng.choice([-4, 4, 1, 1000]))
    elif broken == 'version': struct.pack_into('<I', data, 4, rng.choice([1, 3]))
    elif broken == 'json_length': struct.pack_into('<I', data, 12, len(text) + rng.choice([-1, 1, 4, -4]))
    elif broken == 'chunk_type': data[16:20] = rng.choice([b'BIN\0', b'XXXX', b'json'])
    elif broken == 'extra_chunk': data += struct.pack('<I4s', 4, b'ABCD') + b'1234'; struct.pack_into('<I', data, 8, len(data))
    elif broken == 'bin_first' and blob is not None:
        first = struct.pack('<I4s', len(body), b'BIN\0') + body
        data = bytearray(struct.pack('<4sII', b'glTF', 2, 12 + len(chunks)) + first + struct.pack('<I4s', len(text), b'JSON') + text)
    return bytes(data)


os.makedirs(args.work, exist_ok=True)
suite_root = os.path.join(args.shared, 'validator-suite')
suite_files = sorted(f for f in glob.glob(os.path.join(suite_root, 'test/**/*.gltf'), recursive=True))
extensions = harvest_extensions(suite_files)

# Sources: the synthetic document, the small shared assets (copied with their resources so that
# mutants sit next to them), and the suite's cases (copied with their folders' resources).
sources = []
base_doc, base_blob = synthetic()
sources += [('synthetic', None)] * 8
for name in ['Box', 'BoxInterleaved', 'BoxTextured', 'BoxTexturedNonPowerOfTwo', 'RiggedSimple', 'Duck', 'CesiumMan']:
    for variant in ['specgloss', 'metalrough']:
        folder = os.path.join(args.shared, 'assets', name, variant)
        gltfs = glob.glob(os.path.join(folder, '*.gltf'))
        if not gltfs: continue
        target = os.path.join(args.work, 'assets', name, variant)
        if not os.path.isdir(target): shutil.copytree(folder, target)
        sources.append(('file', os.path.join(target, os.path.basename(gltfs[0]))))
for f in suite_files:
    relative = os.path.relpath(os.path.dirname(f), suite_root)
    target = os.path.join(args.work, 'suite', relative)
    if not os.path.isdir(target): shutil.copytree(os.path.dirname(f), target, ignore=shutil.ignore_patterns('*.report.json'))
    sources.append(('file', os.path.join(target, os.path.basename(f))))

# Half the inputs from the synthetic document, a quarter each from the assets and the suite.
asset_sources = [s for s in sources if s[0] == 'file' and '/assets/' in s[1]]
suite_sources = [s for s in sources if s[0] == 'file' and '/suite/' in s[1]]
written = []
os.makedirs(os.path.join(args.work, 'gen'), exist_ok=True)
for n in range(args.count):
    draw = rng.random()
    if draw < 0.5:
        doc, blob, source_path = copy.deepcopy(base_doc), base_blob, None
    else:
        source_path = rng.choice(asset_sources if draw < 0.75 else suite_sources)[1]
        try: doc = json.load(open(source_path))
        except Exception: continue
        blob = None
    for _ in range(rng.choice([1, 1, 1, 2, 3])):
        try: mutate(doc, extensions)
        except Exception: pass
    if source_path is None:
        if rng.random() < 0.2:
            # GLB: the buffer moves into the BIN chunk; a third of them get a broken container.
            if isinstance(doc.get('buffers'), list) and doc['buffers'] and isinstance(doc['buffers'][0], dict) and 'uri' in doc['buffers'][0] and rng.random() < 0.8:
                del doc['buffers'][0]['uri']
                carried = blob
            else:
                carried = None if rng.random() < 0.5 else blob
            broken = rng.choice(['short', 'length', 'version', 'json_length', 'chunk_type', 'extra_chunk', 'bin_first']) if rng.random() < 0.33 else None
            name = os.path.join(args.work, 'gen', '%05d.glb' % n)
            open(name, 'wb').write(glb(dumps(doc), carried, broken))
        else:
            name = os.path.join(args.work, 'gen', '%05d.gltf' % n)
            open(name, 'w').write(dumps(doc))
    else:
        name = source_path[:-5] + '.gen%05d.gltf' % n
        open(name, 'w').write(dumps(doc))
    written.append(name)
open(os.path.join(args.work, 'list.txt'), 'w').write('\n'.join(written) + '\n')
print(len(written))
