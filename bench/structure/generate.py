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
# With --new-share S, that share of the inputs comes instead from SHAPES: small valid documents, each
# built around one feature the mutations above never reach, with that feature's values varied:
# sparse accessors, KHR material extensions with texture infos, KHR_texture_transform,
# KHR_mesh_quantization, Draco and meshopt objects, images (bufferView, uri, mimeType, data URI media
# types, odd bytes), GLB BIN chunks against their buffers, scenes and node graphs, cameras, skins and
# joint/weight data, animations, accessor and buffer view values, KHR_lights_punctual and
# KHR_materials_variants, extension lists and asset versions, and raw JSON text (escaped or
# duplicate keys, bad UTF-8, BOM, lone surrogates, huge numbers). They are named
# gen/<shape>_NNNNN.gltf|glb so that disagreements group by shape. At S = 0 (the default) a seed
# makes the same inputs as before the shapes existed.
# --shapes-set 2 draws the shapes from SHAPES2 instead: morph targets and weights
# counts, samplers and texture references, primitive modes, index values and attribute names,
# material value combinations, external files, extras and unsupported extensions, accessor bounds
# on every component type, byteStride rules, animation samplers and channels as objects. The
# default (1) makes, seed for seed, the same inputs as before SHAPES2 existed.
# --shapes-set 3 draws them from SHAPES3: vertex attribute sets and formats without quantization,
# index accessors (formats, views, sharing, values per mode), skins in detail (skeletons, shared
# joints, IBM formats and values, JOINTS/WEIGHTS sets), animation channels (weights per morph
# target, duplicate and missing targets, input bounds), EXT_mesh_gpu_instancing,
# KHR_materials_variants in detail, node properties (camera with mesh, matrices near the TRS
# limits, rotations near unit length, graphs across scenes), the asset object and extension lists
# against the extensions present. --shapes-set 4 draws from all three sets.
import argparse, base64, copy, glob, json, math, os, random, shutil, struct, zlib

parser = argparse.ArgumentParser()
parser.add_argument('work')
parser.add_argument('shared')
parser.add_argument('--count', type=int, default=10000)
parser.add_argument('--seed', type=int, default=14)
parser.add_argument('--new-share', type=float, default=0.0,
                    help='share of inputs made from SHAPES (0: the inputs of the original kinds, seed for seed as before)')
parser.add_argument('--shapes-set', type=int, default=1, choices=[1, 2, 3, 4],
                    help='which shapes --new-share draws from: 1 SHAPES (the default, seed for seed as before), 2 SHAPES2, 3 SHAPES3, 4 all three')
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



# ---------------------------------------------------------------------------------------------
# New document shapes (the kinds of input the mutations above do not reach): each builds a small,
# otherwise valid document around one feature and varies that feature's values. Called as
# SHAPES[name]() -> (doc, blob, container) where container is 'gltf' or 'glb' (or raw bytes).
# ---------------------------------------------------------------------------------------------
def pack(fmt, values):
    """Packs values as fmt, clamping integers into the format's range (floats may be NaN)."""
    if fmt == 'f': return struct.pack('<' + 'f' * len(values), *[float(v) for v in values])
    lo, hi = {'b': (-128, 127), 'B': (0, 255), 'h': (-32768, 32767), 'H': (0, 65535), 'I': (0, 2 ** 32 - 1)}[fmt]
    ints = [0 if isinstance(v, float) and v != v else min(hi, max(lo, int(v))) for v in values]
    return struct.pack('<' + fmt * len(ints), *ints)


class Builder:
    """A small valid document (one indexed triangle, a textured material, one node, one scene)
    whose binary grows as shapes add views and accessors; finish() writes the buffer."""
    def __init__(self, uv=True, normals=True, texture=True):
        self.blob = bytearray()
        self.doc = {'asset': {'version': '2.0'}, 'scene': 0, 'scenes': [{'nodes': [0]}], 'nodes': [{'mesh': 0}],
                    'meshes': [], 'accessors': [], 'bufferViews': [], 'buffers': []}
        pos = self.acc('f', [0, 0, 0, 1, 0, 0, 0, 1, 0], 5126, 'VEC3', 3, target=34962, minmax=True)
        attrs = {'POSITION': pos}
        if normals: attrs['NORMAL'] = self.acc('f', [0, 0, 1] * 3, 5126, 'VEC3', 3, target=34962)
        if uv: attrs['TEXCOORD_0'] = self.acc('f', [0, 0, 1, 0, 0, 1], 5126, 'VEC2', 3, target=34962)
        idx = self.acc('H', [0, 1, 2], 5123, 'SCALAR', 3, target=34963)
        prim = {'attributes': attrs, 'indices': idx}
        if texture:
            self.doc['materials'] = [{'pbrMetallicRoughness': {'baseColorTexture': {'index': 0}}}]
            self.doc['textures'] = [{'source': 0, 'sampler': 0}]
            self.doc['samplers'] = [{}]
            self.doc['images'] = [{'uri': data_uri(png(1, 1, (255, 255, 255, 255)), 'image/png')}]
            prim['material'] = 0
        self.doc['meshes'].append({'primitives': [prim]})

    def view(self, data, target=None, stride=None, align=4):
        while len(self.blob) % align: self.blob.append(0)
        offset = len(self.blob)
        self.blob.extend(data)
        v = {'buffer': 0, 'byteLength': len(data)}
        if offset: v['byteOffset'] = offset
        if target: v['target'] = target
        if stride: v['byteStride'] = stride
        self.doc['bufferViews'].append(v)
        return len(self.doc['bufferViews']) - 1

    def acc(self, fmt, values, component, kind, count, target=None, minmax=False, normalized=False, view=True):
        a = {'componentType': component, 'count': count, 'type': kind}
        if view:
            a['bufferView'] = self.view(pack(fmt, values), target)
        if normalized: a['normalized'] = True
        if minmax and values:
            width = len(values) // count
            a['min'] = [min(values[i::width]) for i in range(width)]
            a['max'] = [max(values[i::width]) for i in range(width)]
        self.doc['accessors'].append(a)
        return len(self.doc['accessors']) - 1

    def use(self, name, required=False):
        used = self.doc.setdefault('extensionsUsed', [])
        if name not in used: used.append(name)
        if required and name not in self.doc.setdefault('extensionsRequired', []): self.doc['extensionsRequired'].append(name)

    def prim(self): return self.doc['meshes'][0]['primitives'][0]

    def finish(self, glb_chunk=False):
        while len(self.blob) % 4: self.blob.append(0)
        buf = {'byteLength': len(self.blob)}
        if not glb_chunk: buf['uri'] = data_uri(bytes(self.blob))
        self.doc['buffers'] = [buf]
        return self.doc, bytes(self.blob), 'glb' if glb_chunk else 'gltf'


FMT = {5120: 'b', 5121: 'B', 5122: 'h', 5123: 'H', 5125: 'I', 5126: 'f'}
SIZE = {5120: 1, 5121: 1, 5122: 2, 5123: 2, 5125: 4, 5126: 4}
WIDTH = {'SCALAR': 1, 'VEC2': 2, 'VEC3': 3, 'VEC4': 4, 'MAT2': 4, 'MAT3': 9, 'MAT4': 16}
pick = lambda *xs: rng.choice(xs)


def shape_sparse():
    """Sparse accessors: index component types, sorted/unsorted/duplicate/out-of-range indices,
    count beyond the base, views with strides or targets, no base view, sparse on indices/inputs."""
    b = Builder()
    where = pick('extra', 'position', 'indices', 'anim_input', 'anim_output', 'ibm', 'morph')
    count = 4
    base_vals = [float(i) for i in range(count * 3)]
    n = pick(1, 2, 3, 0, 5)
    idx_ct = pick(5121, 5123, 5125, 5125, 5126, 5120, 5122)
    idx_vals = sorted(rng.sample(range(count), min(n, count))) if n <= count else list(range(n))
    order = pick('sorted', 'sorted', 'unsorted', 'dup', 'oob', 'oob_eq')
    if order == 'unsorted' and len(idx_vals) > 1: idx_vals = idx_vals[::-1]
    if order == 'dup' and idx_vals: idx_vals = [idx_vals[0]] * len(idx_vals)
    if order == 'oob' and idx_vals: idx_vals[-1] = count + pick(1, 100)
    if order == 'oob_eq' and idx_vals: idx_vals[-1] = count
    fmt_i = FMT.get(idx_ct, 'I')
    idx_bytes = struct.pack('<' + fmt_i * len(idx_vals), *[float(v) if fmt_i == 'f' else v for v in idx_vals])
    val_ct, kind = 5126, 'VEC3'
    if where == 'indices': val_ct, kind = pick(5123, 5125, 5121), 'SCALAR'
    if where in ('anim_input',): kind = 'SCALAR'
    if where == 'anim_output': kind = pick('VEC3', 'VEC4')
    if where == 'ibm': kind = 'MAT4'
    w = WIDTH[kind]
    vals = [float(rng.choice([0, 0.5, 1, 2, -1, 100])) if val_ct == 5126 else rng.randrange(0, 6) for _ in range(len(idx_vals) * w)]
    val_bytes = pack(FMT[val_ct], vals)
    iv = b.view(idx_bytes, target=pick(None, None, None, 34963, 34962), stride=pick(None, None, None, 4, 8), align=pick(4, 4, 1))
    vv = b.view(val_bytes, target=pick(None, None, None, 34962), stride=pick(None, None, None, 12, 16))
    sparse = {'count': pick(len(idx_vals), len(idx_vals), len(idx_vals), 0, len(idx_vals) + 1, count + 1),
              'indices': {'bufferView': iv, 'componentType': idx_ct},
              'values': {'bufferView': vv}}
    if rng.random() < 0.2: sparse['indices']['byteOffset'] = pick(1, 2, 3, 4, 100)
    if rng.random() < 0.2: sparse['values']['byteOffset'] = pick(1, 2, 4, 100)
    if rng.random() < 0.1: del sparse[pick('indices', 'values')]
    if rng.random() < 0.1 and 'indices' in sparse: sparse['indices']['bufferView'] = 99
    base_kind_vals = [0.0] * (count * w) if val_ct == 5126 else [0] * (count * w)
    if where == 'anim_input': base_kind_vals = [float(i) for i in range(count)]
    has_view = rng.random() < 0.6
    a = b.acc(FMT[val_ct], base_kind_vals, val_ct, kind, count, view=has_view, minmax=rng.random() < 0.6)
    b.doc['accessors'][a]['sparse'] = sparse
    if where == 'position':
        b.prim()['attributes']['POSITION'] = a
        for k in ('NORMAL', 'TEXCOORD_0'):
            b.prim()['attributes'].pop(k, None)
        b.doc['materials'] = [{}]; b.doc.pop('textures'); b.doc.pop('samplers'); b.doc.pop('images')
        b.doc['accessors'][a].setdefault('min', [0, 0, 0]); b.doc['accessors'][a].setdefault('max', [pick(0, 1, 100)] * 3)
        b.prim()['indices'] = b.acc('H', [0, 1, 2, 1, 2, 3], 5123, 'SCALAR', 6, target=34963)
    elif where == 'indices':
        b.prim()['indices'] = a
        b.doc['accessors'][a]['count'] = 3
    elif where in ('anim_input', 'anim_output'):
        inp = b.acc('f', [0, 1, 2, 3], 5126, 'SCALAR', 4, minmax=True)
        out = b.acc('f', [0, 0, 0, 1] * 4 if kind == 'VEC4' else [0] * 12, 5126, kind, 4)
        if where == 'anim_input': inp = a
        else: out = a
        b.doc['animations'] = [{'samplers': [{'input': inp, 'output': out}],
                                'channels': [{'sampler': 0, 'target': {'node': 0, 'path': 'rotation' if kind == 'VEC4' else 'translation'}}]}]
    elif where == 'ibm':
        b.doc['nodes'] = [{'mesh': 0, 'skin': 0}, {'children': []}, {}]
        b.doc['scenes'][0]['nodes'] = [0, 1]
        b.doc['nodes'][1]['children'] = [2]
        b.prim()['attributes']['JOINTS_0'] = b.acc('B', [0, 1, 0, 0] * 3, 5121, 'VEC4', 3, target=34962)
        b.prim()['attributes']['WEIGHTS_0'] = b.acc('f', [0.5, 0.5, 0, 0] * 3, 5126, 'VEC4', 3, target=34962)
        b.doc['skins'] = [{'joints': [1, 2, 2, 1][:count], 'inverseBindMatrices': a}]
        b.doc['skins'][0]['joints'] = [1, 2] + [1] * 0
        b.doc['accessors'][a]['count'] = 2
    elif where == 'morph':
        b.prim()['targets'] = [{'POSITION': a}]
        b.doc['accessors'][a]['count'] = 3
        b.doc['accessors'][a].setdefault('min', [0, 0, 0]); b.doc['accessors'][a].setdefault('max', [0, 0, 0])
    return b.finish()


TEXTURE_EXTS = {
    'KHR_materials_clearcoat': {'clearcoatFactor': 1, 'clearcoatTexture': 'ti', 'clearcoatRoughnessFactor': 0.5,
                                'clearcoatRoughnessTexture': 'ti', 'clearcoatNormalTexture': 'nti'},
    'KHR_materials_sheen': {'sheenColorFactor': [1, 1, 1], 'sheenColorTexture': 'ti', 'sheenRoughnessFactor': 0.5, 'sheenRoughnessTexture': 'ti'},
    'KHR_materials_specular': {'specularFactor': 1, 'specularTexture': 'ti', 'specularColorFactor': [1, 1, 1], 'specularColorTexture': 'ti'},
    'KHR_materials_transmission': {'transmissionFactor': 0.5, 'transmissionTexture': 'ti'},
    'KHR_materials_volume': {'thicknessFactor': 1, 'thicknessTexture': 'ti', 'attenuationDistance': 1, 'attenuationColor': [1, 1, 1]},
    'KHR_materials_ior': {'ior': 1.5},
    'KHR_materials_iridescence': {'iridescenceFactor': 1, 'iridescenceTexture': 'ti', 'iridescenceIor': 1.3,
                                  'iridescenceThicknessMinimum': 100, 'iridescenceThicknessMaximum': 400, 'iridescenceThicknessTexture': 'ti'},
    'KHR_materials_anisotropy': {'anisotropyStrength': 0.5, 'anisotropyRotation': 1, 'anisotropyTexture': 'ti'},
    'KHR_materials_emissive_strength': {'emissiveStrength': 2},
    'KHR_materials_dispersion': {'dispersion': 0.1},
    'KHR_materials_unlit': {},
    'KHR_materials_pbrSpecularGlossiness': {'diffuseFactor': [1, 1, 1, 1], 'diffuseTexture': 'ti', 'specularFactor': [1, 1, 1],
                                            'glossinessFactor': 1, 'specularGlossinessTexture': 'ti'},
}
ODD_NUMBERS = [-1, -0.5, 0, 0.5, 1, 1.5, 2, 1000, -1000, 1e-45, 'x', None, True, [1], {}]


def texinfo(normal=False):
    t = {'index': 0}
    r = rng.random()
    if r < 0.3: t['texCoord'] = pick(0, 1, 2, -1, 0.5, 'x', 10)
    if r < 0.1: t['index'] = pick(1, -1, 'x', 0.0)
    if normal and rng.random() < 0.3: t['scale'] = pick(0, -1, 2, 'x')
    if rng.random() < 0.3:
        tt = {}
        for k in rng.sample(['offset', 'rotation', 'scale', 'texCoord', 'foo'], rng.randrange(0, 4)):
            tt[k] = {'offset': pick([0, 0], [1, 2, 3], [1], 'x', [0, 'a']), 'rotation': pick(0, 1.57, -7, 'x', [1]),
                     'scale': pick([1, 1], [0, 0], [-1, 2], [1, 1, 1], 2), 'texCoord': pick(0, 1, 2, -1, 1.5),
                     'foo': 1}[k]
        t['extensions'] = {'KHR_texture_transform': tt}
    return t


def shape_material_ext():
    """KHR material extensions: odd property values, texture infos inside them (texCoord beyond
    the mesh's sets, KHR_texture_transform), combinations the catalogue names, declared or not."""
    b = Builder(uv=rng.random() < 0.8, normals=rng.random() < 0.8)
    mat = b.doc['materials'][0]
    names = rng.sample(sorted(TEXTURE_EXTS), rng.choice([1, 1, 2, 3]))
    exts = mat.setdefault('extensions', {})
    for name in names:
        body = {}
        for k, v in TEXTURE_EXTS[name].items():
            if rng.random() < 0.5: continue
            if v == 'ti' or v == 'nti': body[k] = texinfo(v == 'nti')
            elif rng.random() < 0.35: body[k] = rng.choice(ODD_NUMBERS) if not isinstance(v, list) else pick([2, 2, 2], [-1, 0, 0], [1, 1], [1, 1, 1, 1], 'x', [1, 'x', 1])
            else: body[k] = v
        if rng.random() < 0.1: body['extra_member'] = 1
        exts[name] = body
        if rng.random() < 0.9: b.use(name)
    if 'KHR_texture_transform' in json.dumps(mat) and rng.random() < 0.9: b.use('KHR_texture_transform')
    if rng.random() < 0.3: mat['normalTexture'] = texinfo(True)
    if rng.random() < 0.3: mat['emissiveFactor'] = pick([0, 0, 0], [1, 1, 1], [2, 0, 0])
    if rng.random() < 0.3: mat['doubleSided'] = pick(True, False)
    if rng.random() < 0.3: mat['occlusionTexture'] = dict(texinfo(), strength=pick(0, 1, 2, -1))
    if rng.random() < 0.2: mat['pbrMetallicRoughness']['baseColorTexture'] = texinfo()
    if rng.random() < 0.2: b.prim()['attributes']['TEXCOORD_1'] = b.prim()['attributes'].get('TEXCOORD_0', 0)
    if rng.random() < 0.2: b.prim()['attributes']['TANGENT'] = b.acc('f', [1, 0, 0, 1] * 3, 5126, 'VEC4', 3, target=34962)
    return b.finish()


def shape_texture_transform():
    """KHR_texture_transform in every texture info of a material, with texCoord overrides."""
    b = Builder()
    mat = b.doc['materials'][0]
    slot = pick('base', 'normal', 'occlusion', 'emissive', 'mr')
    ti = texinfo(slot == 'normal')
    tt = {pick('offset', 'rotation', 'scale', 'texCoord'): None}
    k = next(iter(tt))
    tt[k] = {'offset': pick([0.5, 0.5], [0], [0, 0, 0], ['a', 0], 'x', [1e400, 0]), 'rotation': pick(0.5, -100, 'x', [0], 1e400),
             'scale': pick([2, 2], [0, 0], [-1, -1], [1], 'x'), 'texCoord': pick(0, 1, 2, -1, 0.5, 'x', 2 ** 32)}[k]
    if rng.random() < 0.2: tt = pick({}, [], 'x', None)
    ti['extensions'] = {'KHR_texture_transform': tt}
    if slot == 'base': mat['pbrMetallicRoughness']['baseColorTexture'] = ti
    elif slot == 'mr': mat['pbrMetallicRoughness']['metallicRoughnessTexture'] = ti
    else: mat[slot + 'Texture'] = ti
    if rng.random() < 0.85: b.use('KHR_texture_transform', required=rng.random() < 0.2)
    if rng.random() < 0.3: b.prim()['attributes']['TEXCOORD_1'] = b.prim()['attributes']['TEXCOORD_0']
    if rng.random() < 0.2: b.doc['extensionsUsed'] = ['KHR_texture_transform'] * 2
    return b.finish()


def shape_quantization():
    """KHR_mesh_quantization: attributes in byte/short forms, normalized or not, declared or not;
    unaligned VEC3 byte attributes; the same outside the extension."""
    b = Builder(texture=rng.random() < 0.5)
    sem = pick('POSITION', 'NORMAL', 'TANGENT', 'TEXCOORD_0', 'COLOR_0', 'JOINTS_0', 'WEIGHTS_0', 'TEXCOORD_0')
    ct = pick(5120, 5121, 5122, 5123, 5125, 5126)
    norm = rng.random() < 0.5
    kind = {'POSITION': 'VEC3', 'NORMAL': 'VEC3', 'TANGENT': 'VEC4', 'TEXCOORD_0': 'VEC2', 'COLOR_0': pick('VEC3', 'VEC4'),
            'JOINTS_0': 'VEC4', 'WEIGHTS_0': 'VEC4'}[sem]
    if rng.random() < 0.1: kind = pick('SCALAR', 'VEC2', 'VEC3', 'VEC4', 'MAT2')
    w = WIDTH[kind]
    if ct == 5126: vals = [0.0] * (3 * w)
    else: vals = [rng.choice([0, 1]) for _ in range(3 * w)]
    if sem in ('NORMAL',) and ct != 5126 and norm: vals = [0, 0, 127 if ct in (5120, 5121) else 32767] * 3
    stride = pick(None, None, 4 * ((SIZE[ct] * w + 3) // 4))
    data = pack(FMT[ct], vals)
    v = b.view(data, target=34962, stride=stride)
    a = {'bufferView': v, 'componentType': ct, 'count': 3, 'type': kind}
    if norm: a['normalized'] = True
    if sem == 'POSITION' or rng.random() < 0.2:
        a['min'] = [min(vals[i::w]) for i in range(w)]; a['max'] = [max(vals[i::w]) for i in range(w)]
    b.doc['accessors'].append(a)
    b.prim()['attributes'][sem] = len(b.doc['accessors']) - 1
    if sem == 'JOINTS_0' and 'WEIGHTS_0' not in b.prim()['attributes']:
        b.prim()['attributes']['WEIGHTS_0'] = b.acc('f', [1, 0, 0, 0] * 3, 5126, 'VEC4', 3, target=34962)
    if sem == 'WEIGHTS_0' and 'JOINTS_0' not in b.prim()['attributes']:
        b.prim()['attributes']['JOINTS_0'] = b.acc('B', [0, 0, 0, 0] * 3, 5121, 'VEC4', 3, target=34962)
    if rng.random() < 0.3:  # morph target in a quantized form too
        b.prim()['targets'] = [{'POSITION': b.acc('b', [0, 0, 1] * 3, 5120, 'VEC3', 3, target=34962, minmax=True, normalized=rng.random() < 0.5)}]
    if rng.random() < 0.7: b.use('KHR_mesh_quantization', required=rng.random() < 0.8)
    return b.finish()


def shape_compression():
    """EXT_meshopt_compression on buffer views and KHR_draco_mesh_compression on primitives."""
    b = Builder(texture=False)
    if rng.random() < 0.5:
        bv = b.doc['bufferViews'][0]
        ext = {'buffer': pick(0, 0, 1, -1), 'byteLength': pick(bv['byteLength'], 1000, 0), 'byteStride': pick(12, 3, 0, 300),
               'count': pick(3, 0, -1), 'mode': pick('ATTRIBUTES', 'TRIANGLES', 'INDICES', 'x'), 'filter': pick(None, 'NONE', 'OCTAHEDRAL', 'x')}
        if ext['filter'] is None: del ext['filter']
        if rng.random() < 0.3: ext['byteOffset'] = pick(0, 1, 4)
        if rng.random() < 0.2: del ext[pick('buffer', 'byteLength', 'byteStride', 'count', 'mode')]
        bv['extensions'] = {'EXT_meshopt_compression': ext}
        name = 'EXT_meshopt_compression'
        if rng.random() < 0.3:
            b.doc['buffers_extra'] = True
    else:
        ext = {'bufferView': pick(0, 1, 99, -1), 'attributes': pick({'POSITION': 0}, {'POSITION': 0, 'NORMAL': 1}, {'TEXCOORD_0': 0}, {}, {'POSITION': 'x'})}
        if rng.random() < 0.2: del ext[pick('bufferView', 'attributes')]
        b.prim()['extensions'] = {'KHR_draco_mesh_compression': ext}
        name = 'KHR_draco_mesh_compression'
        if rng.random() < 0.3: b.prim()['mode'] = pick(0, 1, 5)
    if rng.random() < 0.8: b.use(name, required=rng.random() < 0.7)
    doc, blob, c = b.finish()
    if doc.pop('buffers_extra', None):
        doc['buffers'].append({'byteLength': 16, 'extensions': {'EXT_meshopt_compression': {'fallback': pick(True, False, 1)}}})
    return doc, blob, c


def shape_images():
    """Images: bufferView + mimeType combinations, uri and bufferView together, data URIs of odd
    media types, image bytes that do not match the declared type, webp/ktx2 sources."""
    b = Builder()
    payloads = {'png': png(1, 1, (1, 2, 3, 255)), 'jpeg': b'\xff\xd8\xff\xe0\0\x10JFIF\0' + b'\0' * 8, 'gif': b'GIF89a\1\0\1\0\0\0\0;',
                'webp': b'RIFF\x1a\0\0\0WEBPVP8L\x0d\0\0\0\x2f\0\0\0\x10\x07\x10\x11\x11\x88\x88\xfe\x07\0',
                'ktx2': b'\xabKTX 20\xbb\r\n\x1a\n' + b'\0' * 20, 'junk': b'hello world!', 'empty': b'', 'cut_png': png(1, 1, (1, 2, 3, 255))[:20]}
    kind = pick(*payloads)
    data = payloads[kind]
    img = {}
    mode = pick('bufferView', 'bufferView', 'data', 'both', 'none')
    if mode in ('bufferView', 'both'):
        img['bufferView'] = b.view(data or b'\0', stride=pick(None, None, None, 4), target=pick(None, None, None, 34962))
        if rng.random() < 0.8: img['mimeType'] = pick('image/png', 'image/jpeg', 'image/webp', 'image/ktx2', 'image/gif', 'image/PNG', '')
    if mode in ('data', 'both'):
        img['uri'] = data_uri(data, pick('image/png', 'image/jpeg', 'image/gif', 'image/webp', 'image/ktx2', 'application/octet-stream', 'text/plain', ''))
        if rng.random() < 0.3: img['mimeType'] = pick('image/png', 'image/jpeg', 'image/webp')
    if mode == 'none' and rng.random() < 0.5: img['mimeType'] = 'image/png'
    b.doc['images'] = [img]
    if rng.random() < 0.2: b.doc['images'].append({'uri': pick('a.png', 'x.gif', 'http://example.com/a.png', 'data:image/png,abc', 'data:image/png;base64,')})
    tex = b.doc['textures'][0]
    if rng.random() < 0.25:
        ext = pick('EXT_texture_webp', 'KHR_texture_basisu')
        tex['extensions'] = {ext: {'source': pick(0, 0, 1, -1)}}
        if rng.random() < 0.5: del tex['source']
        if rng.random() < 0.8: b.use(ext, required=rng.random() < 0.5)
    return b.finish(glb_chunk=rng.random() < 0.3)


def shape_glb_buffers():
    """GLB containers whose BIN chunk and buffers disagree: a BIN chunk and a buffer with a uri,
    no BIN chunk and no uri, two uri-less buffers, BIN longer/shorter than byteLength, empty BIN."""
    b = Builder(texture=False)
    doc, blob, _ = b.finish(glb_chunk=True)
    variant = pick('uri_and_bin', 'no_bin', 'two_uriless', 'bin_longer', 'bin_shorter', 'empty_bin', 'uri_second', 'data_uri_in_glb')
    if variant == 'uri_and_bin': doc['buffers'][0]['uri'] = data_uri(blob)
    if variant == 'no_bin': blob = None
    if variant == 'two_uriless': doc['buffers'].append({'byteLength': 4})
    if variant == 'bin_longer': blob = blob + b'\0' * pick(4, 8, 64)
    if variant == 'bin_shorter': doc['buffers'][0]['byteLength'] += pick(1, 4, 100)
    if variant == 'empty_bin': blob = b''; doc['buffers'][0]['byteLength'] = pick(0, 1)
    if variant == 'uri_second':
        doc['buffers'].insert(0, {'byteLength': len(blob), 'uri': data_uri(blob)})
    if variant == 'data_uri_in_glb':
        doc['images'] = [{'uri': data_uri(png(1, 1, (1, 1, 1, 255)), 'image/png')}]
        doc['textures'] = [{'source': 0}]
    return doc, blob, 'glb'


def shape_scenes_nodes():
    """Scenes and node graphs: several scenes, scene index out of range, non-root nodes in a scene,
    repeated nodes, cycles, self-children, multiple parents, matrix forms (non-TRS, default, with TRS)."""
    b = Builder(texture=False)
    n = 5
    nodes = [{} for _ in range(n)]
    nodes[0]['mesh'] = 0
    edges = pick('chain', 'cycle', 'self', 'two_parents', 'dup_child', 'tree')
    if edges == 'chain': nodes[1]['children'] = [2]; nodes[2]['children'] = [3]
    if edges == 'cycle': nodes[1]['children'] = [2]; nodes[2]['children'] = [3]; nodes[3]['children'] = [1]
    if edges == 'self': nodes[1]['children'] = [1]
    if edges == 'two_parents': nodes[1]['children'] = [3]; nodes[2]['children'] = [3]
    if edges == 'dup_child': nodes[1]['children'] = [2, 2]
    if edges == 'tree': nodes[1]['children'] = [2, 3]; nodes[3]['children'] = [4]
    b.doc['nodes'] = nodes
    scenes = [{'nodes': rng.sample(range(n), rng.randrange(1, 4))} for _ in range(rng.choice([1, 2, 3]))]
    if rng.random() < 0.2: scenes[0]['nodes'].append(scenes[0]['nodes'][0])
    if rng.random() < 0.2: scenes.append({})
    if rng.random() < 0.1: scenes.append({'nodes': []})
    b.doc['scenes'] = scenes
    b.doc['scene'] = pick(0, len(scenes) - 1, len(scenes), -1)
    if rng.random() < 0.2: del b.doc['scene']
    if rng.random() < 0.4:
        node = rng.choice(nodes)
        node['matrix'] = pick([1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1], [0] * 16, [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 2],
                              [1, 1, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1], [2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 5, 5, 5, 1],
                              [-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1], [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0])
        if rng.random() < 0.3: node[pick('translation', 'rotation', 'scale')] = pick([0, 0, 0], [0, 0, 0, 1], [1, 1, 1])
    if rng.random() < 0.3:
        rng.choice(nodes)['rotation'] = pick([0, 0, 0, 1], [0, 0, 0, 2], [0, 0, 0, 0], [0.5, 0.5, 0.5, 0.5], [0, 0, 0, 0.99999])
    if rng.random() < 0.2:
        rng.choice(nodes)['scale'] = pick([0, 0, 0], [1, 1, 1], [-1, 1, 1])
    return b.finish()


def shape_cameras():
    """Cameras: zfar <= znear, zfar 0/absent, aspectRatio 0, yfov >= pi or 0, xmag/ymag 0 or negative,
    both or neither projections, the projection not matching type."""
    b = Builder(texture=False)
    t = pick('perspective', 'orthographic', 'x')
    cam = {'type': t}
    p = {'yfov': pick(0.8, 0, -1, math.pi, 4, 1e-9), 'znear': pick(0.1, 0, -1, 10, 100), 'zfar': pick(100, 0.1, 0, -5, 1e400, None),
         'aspectRatio': pick(1.5, 0, -1, None)}
    o = {'xmag': pick(1, 0, -1, 0.0), 'ymag': pick(1, 0, -1), 'znear': pick(0, 0.1, -1, 10), 'zfar': pick(10, 0, 0.1, -1, 10)}
    p = {k: v for k, v in p.items() if v is not None}
    which = pick('match', 'match', 'both', 'neither', 'swap')
    proj = 'orthographic' if t == 'orthographic' else 'perspective'
    if which == 'match': cam[proj] = p if proj == 'perspective' else o
    if which == 'both': cam['perspective'] = p; cam['orthographic'] = o
    if which == 'swap': cam['orthographic' if proj == 'perspective' else 'perspective'] = o if proj == 'perspective' else p
    b.doc['cameras'] = [cam]
    b.doc['nodes'].append({'camera': pick(0, 0, 1)})
    b.doc['scenes'][0]['nodes'].append(1)
    return b.finish()


def shape_skins():
    """Skins: joints without a common root, skeleton not a common root, duplicate joints, joints
    outside the scene, skinned node with local/parent transforms or not a root, IBM count/format,
    joints/weights data (duplicates, out of range, zero weight, negative, non-normalized)."""
    b = Builder(texture=False)
    p = b.prim()
    jv = [[0, 1, 0, 0], [1, 1, 0, 0], [0, 5, 0, 0], [0, 1, 2, 0], [1, 0, 0, 0]]
    wv = [[0.5, 0.5, 0, 0], [1, 0, 0, 0], [0.7, 0.7, 0, 0], [-0.5, 1.5, 0, 0], [0.5, 0.25, 0.25, 0], [1, 0, 0, 0]]
    j = pick(*jv); w = pick(*wv)
    jct = pick(5121, 5121, 5123, 5125, 5126)
    wct = pick(5126, 5126, 5121, 5123)
    wvals = w * 3 if wct == 5126 else [int(round(max(0, x) * (255 if wct == 5121 else 65535))) for x in w] * 3
    p['attributes']['JOINTS_0'] = b.acc(FMT[jct], j * 3, jct, 'VEC4', 3, target=34962)
    p['attributes']['WEIGHTS_0'] = b.acc(FMT[wct], wvals, wct, 'VEC4', 3, target=34962, normalized=wct != 5126)
    if rng.random() < 0.2: del p['attributes'][pick('JOINTS_0', 'WEIGHTS_0')]
    if rng.random() < 0.15: p['attributes']['JOINTS_1'] = p['attributes'].get('JOINTS_0', 0)
    layout = pick('flat_roots', 'common', 'skeleton_wrong', 'joint_outside_scene', 'skin_node_child', 'dup_joints')
    nodes = [{'mesh': 0, 'skin': 0}, {'children': [2]}, {}, {}, {'children': [0]}]
    joints = [1, 2]
    skin = {'joints': joints}
    if layout == 'flat_roots': joints[:] = [2, 3]; nodes[1]['children'] = []
    if layout == 'skeleton_wrong': skin['skeleton'] = pick(2, 3, 0, 9)
    if layout == 'common' and rng.random() < 0.5: skin['skeleton'] = 1
    if layout == 'dup_joints': joints[:] = [1, 2, 2]
    scene = [0, 1] if layout != 'joint_outside_scene' else [0]
    if layout == 'skin_node_child': scene = [4, 1]; nodes[4]['translation'] = pick([1, 0, 0], [0, 0, 0])
    if rng.random() < 0.2: nodes[0]['translation'] = [1, 0, 0]
    if rng.random() < 0.3:
        n = len(joints) + pick(0, 0, -1, 1)
        ibm_ct, ibm_t = pick((5126, 'MAT4'), (5126, 'MAT4'), (5126, 'MAT3'), (5123, 'MAT4'))
        vals = ([1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1] if ibm_t == 'MAT4' else [1, 0, 0, 0, 1, 0, 0, 0, 1]) * max(n, 0)
        if rng.random() < 0.2 and vals: vals[3] = 5
        skin['inverseBindMatrices'] = b.acc(FMT[ibm_ct], vals, ibm_ct, ibm_t, max(n, 1) if vals else 1)
        if rng.random() < 0.15: b.doc['bufferViews'][-1]['byteStride'] = 64
    if rng.random() < 0.1: nodes[0].pop('skin')
    if rng.random() < 0.1: nodes[3]['mesh'] = 0
    b.doc['nodes'] = nodes
    b.doc['skins'] = [skin]
    b.doc['scenes'] = [{'nodes': scene}]
    if rng.random() < 0.2: b.doc['scenes'].append({'nodes': [3]}); nodes[3]['skin'] = 0; nodes[3]['mesh'] = 0
    return b.finish()


def shape_animation():
    """Animations: weights channels on meshes without morph targets or nodes without meshes, TRS on
    matrix nodes or skinned nodes, duplicate targets, input/output counts, bounds, strides, data."""
    b = Builder(texture=False)
    morph = rng.random() < 0.4
    if morph:
        b.prim()['targets'] = [{'POSITION': b.acc('f', [0, 0, 1] * 3, 5126, 'VEC3', 3, target=34962, minmax=True)}]
        if rng.random() < 0.5: b.doc['meshes'][0]['weights'] = pick([0], [0, 0], [])
    b.doc['nodes'].append({}); b.doc['scenes'][0]['nodes'].append(1)
    if rng.random() < 0.2: b.doc['nodes'][0]['matrix'] = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]
    if rng.random() < 0.2: b.doc['nodes'][0]['weights'] = pick([0], [0, 1])
    path = pick('translation', 'rotation', 'scale', 'weights', 'weights', 'x')
    node = pick(0, 0, 1, 5)
    interp = pick('LINEAR', 'STEP', 'CUBICSPLINE', None)
    times = pick([0, 1], [0, 1, 2], [1, 0], [-1, 0], [0, 0], [0], [0, float('nan')])
    ict = pick(5126, 5126, 5126, 5123)
    inp = b.acc(FMT[ict], times, ict, 'SCALAR', len(times), minmax=rng.random() < 0.8)
    if rng.random() < 0.1: b.doc['bufferViews'][-1]['byteStride'] = 4
    k = {'translation': 'VEC3', 'scale': 'VEC3', 'rotation': 'VEC4', 'weights': 'SCALAR', 'x': 'VEC3'}[path]
    w = WIDTH[k]
    targets = max(1, len(b.prim().get('targets', [])))
    per = targets if path == 'weights' else 1
    n = len(times) * per * (3 if interp == 'CUBICSPLINE' else 1) + pick(0, 0, 0, 1, -1)
    oct_ = pick(5126, 5126, 5126, 5120, 5122, 5121)
    vals = ([0, 0, 0, 1] if k == 'VEC4' else [0.5] * w) * max(n, 0)
    if k == 'VEC4' and rng.random() < 0.3 and vals: vals[3] = 0.5
    if oct_ != 5126: vals = [int(v * (127 if oct_ == 5120 else 32767 if oct_ == 5122 else 255)) for v in vals]
    out = b.acc(FMT[oct_], vals, oct_, k, max(n, 1), normalized=oct_ != 5126 and rng.random() < 0.8) if vals else b.acc('f', [0.0] * w, 5126, k, 1)
    sampler = {'input': inp, 'output': out}
    if interp: sampler['interpolation'] = interp
    ch = {'sampler': 0, 'target': {'node': node, 'path': path}}
    chans = [ch]
    if rng.random() < 0.2: chans.append(copy.deepcopy(ch))
    if rng.random() < 0.1: del ch['target']['node']
    b.doc['animations'] = [{'samplers': [sampler], 'channels': chans}]
    if rng.random() < 0.1:
        b.doc['animations'][0]['channels'][0]['target'] = {'path': 'pointer', 'extensions': {'KHR_animation_pointer': {'pointer': pick('/nodes/0/translation', '/nodes/9/translation', 'x', '/materials/0/emissiveFactor')}}}
        b.use('KHR_animation_pointer')
    return b.finish()


def shape_accessors():
    """Accessor and buffer view values: normalized on float/int, min/max of wrong length or type,
    byteOffset alignment, matrices' column alignment, byteStride on index views, too small/large
    strides, overlapping views, counts 0 or huge, a view used as both index and vertex data."""
    b = Builder(texture=False)
    acc = b.doc['accessors']
    p = b.prim()
    v = pick('normalized', 'minmax_len', 'minmax_type', 'offset_align', 'matrix', 'index_stride', 'small_stride',
             'big_stride', 'overlap', 'count', 'usage_override', 'unequal_count', 'index_data', 'mode', 'float_data', 'bad_ct')
    if v == 'normalized': acc[pick(0, 1, 3)]['normalized'] = pick(True, False, 1)
    if v == 'minmax_len': acc[0]['min'] = pick([0, 0], [0, 0, 0, 0], [], [0, 0, 'x']); acc[3]['max'] = pick([2], [2, 2], [])
    if v == 'minmax_type': acc[3]['min'] = pick([0.5], [-1], [1e400]); acc[3]['max'] = pick([2.0], [2.5], [65536])
    if v == 'offset_align':
        i = pick(0, 1, 3); acc[i]['byteOffset'] = pick(1, 2, 3, 4, 6)
        b.doc['bufferViews'][acc[i]['bufferView']]['byteLength'] += 8
        if rng.random() < 0.5: b.doc['bufferViews'][acc[i]['bufferView']]['byteOffset'] = b.doc['bufferViews'][acc[i]['bufferView']].get('byteOffset', 0) + pick(1, 2)
    if v == 'matrix':
        ct, t = pick((5121, 'MAT2'), (5121, 'MAT3'), (5122, 'MAT3'), (5126, 'MAT2'), (5120, 'MAT4'))
        a = b.acc(FMT[ct], [0] * (WIDTH[t] * 2), ct, t, 2)
        if rng.random() < 0.5: b.doc['bufferViews'][-1]['byteStride'] = pick(4, 8, 12, 16)
    if v == 'index_stride': b.doc['bufferViews'][acc[3]['bufferView']]['byteStride'] = pick(2, 4, 6)
    if v == 'small_stride': b.doc['bufferViews'][acc[0]['bufferView']]['byteStride'] = pick(4, 8, 6, 13)
    if v == 'big_stride': b.doc['bufferViews'][acc[1]['bufferView']]['byteStride'] = pick(40, 252, 256, 36)
    if v == 'overlap': b.doc['bufferViews'][1]['byteOffset'] = pick(0, 4, 12)
    if v == 'count': acc[pick(0, 1, 3)]['count'] = pick(0, 2, 4, 2 ** 31, 2 ** 40)
    if v == 'usage_override': p['indices'] = pick(0, 1, 2); acc[pick(0, 1, 2)]['componentType'] = pick(5125, 5123)
    if v == 'unequal_count':
        p['attributes']['TEXCOORD_0'] = b.acc('f', [0.0] * 8, 5126, 'VEC2', 4, target=34962)
    if v == 'index_data':
        vals = pick([0, 1, 3], [0, 1, 65535], [0, 0, 1], [0, 1, 2, 3], [0, 1, 2, 2, 2, 1])
        ct = pick(5123, 5121, 5125)
        p['indices'] = b.acc(FMT[ct], [min(x, (1 << (8 * SIZE[ct])) - 1) for x in vals], ct, 'SCALAR', len(vals), target=34963)
        if rng.random() < 0.3: p['mode'] = pick(0, 1, 2, 3, 5, 6)
    if v == 'mode':
        p['mode'] = pick(0, 1, 2, 3, 5, 6, 7)
        if rng.random() < 0.5: del p['indices']
    if v == 'float_data':
        sem = pick('NORMAL', 'TANGENT', 'COLOR_0', 'POSITION')
        if sem == 'NORMAL': p['attributes']['NORMAL'] = b.acc('f', pick([0, 0, 2], [0, 0, 0], [float('nan'), 0, 1]) * 3, 5126, 'VEC3', 3, target=34962)
        if sem == 'TANGENT': p['attributes']['TANGENT'] = b.acc('f', [1, 0, 0, pick(0, 2, 1)] * 3, 5126, 'VEC4', 3, target=34962)
        if sem == 'COLOR_0': p['attributes']['COLOR_0'] = b.acc('f', [1.5, 0, 0, -1] * 3, 5126, 'VEC4', 3, target=34962)
        if sem == 'POSITION': acc[0]['max'] = pick([1, 1, 1], [1, 1, 0.5], [1, 1, 0])
    if v == 'bad_ct': acc[pick(0, 1, 2, 3)]['componentType'] = pick(5124, 5130, 5120, 5125)
    return b.finish()


def shape_lights_variants():
    """KHR_lights_punctual (spot cone angles, range, type, intensity, unresolved lights) and
    KHR_materials_variants (mappings, duplicate variants, unresolved indices)."""
    b = Builder()
    if rng.random() < 0.6:
        t = pick('point', 'spot', 'directional', 'area')
        light = {'type': t}
        if rng.random() < 0.5: light['intensity'] = pick(-1, 0, 1, 'x')
        if rng.random() < 0.3: light['range'] = pick(0, -1, 10)
        if rng.random() < 0.4: light['color'] = pick([1, 1, 1], [2, 0, 0], [1, 1], [-1, 0, 0])
        if t == 'spot' or rng.random() < 0.2:
            light['spot'] = {k: v for k, v in (('innerConeAngle', pick(0, 0.5, 1, -0.1, None)), ('outerConeAngle', pick(0.5, 0.5, 0, 2, 1.6, None))) if v is not None}
        b.doc['extensions'] = {'KHR_lights_punctual': {'lights': [light] * pick(1, 1, 2)}}
        b.doc['nodes'].append({'extensions': {'KHR_lights_punctual': {'light': pick(0, 0, 1, 2, -1)}}})
        b.doc['scenes'][0]['nodes'].append(1)
        if rng.random() < 0.9: b.use('KHR_lights_punctual')
    else:
        variants = [{'name': 'a'}, {'name': 'b'}][:pick(1, 2)]
        b.doc['extensions'] = {'KHR_materials_variants': {'variants': variants}}
        b.doc['materials'].append({})
        maps = [{'material': pick(0, 1, 2), 'variants': pick([0], [0, 0], [1], [0, 1], [5], [])} for _ in range(pick(1, 2))]
        b.prim()['extensions'] = {'KHR_materials_variants': {'mappings': maps}}
        if rng.random() < 0.9: b.use('KHR_materials_variants')
    return b.finish()


def shape_extension_lists():
    """extensionsUsed/extensionsRequired: duplicates, required but not used, names of bad format,
    extensions placed on the wrong object, unknown vendor prefixes, and asset versions/minVersion."""
    b = Builder()
    d = b.doc
    v = pick('dup_used', 'req_not_used', 'bad_name', 'wrong_place', 'asset', 'used_unused', 'empty_lists')
    if v == 'dup_used': d['extensionsUsed'] = ['KHR_materials_unlit', 'KHR_materials_unlit']; d['materials'][0]['extensions'] = {'KHR_materials_unlit': {}}
    if v == 'req_not_used': d['extensionsRequired'] = [pick('KHR_materials_unlit', 'EXT_foo', 'KHR_texture_transform')]
    if v == 'bad_name':
        name = pick('khr_foo', 'KHR', 'KHR_', 'foo', 'KHR__x', '_KHR_x', 'KHR-foo', 'EXT_x_y')
        d['extensionsUsed'] = [name]; d['nodes'][0]['extensions'] = {name: {}}
    if v == 'wrong_place':
        name, body = pick(('KHR_materials_unlit', {}), ('KHR_texture_transform', {}), ('KHR_lights_punctual', {'light': 0}),
                          ('KHR_materials_variants', {'mappings': []}), ('KHR_mesh_quantization', {}), ('EXT_texture_webp', {'source': 0}))
        holder = pick(d['nodes'][0], d['materials'][0], d['textures'][0], d['images'][0], d['meshes'][0], d['asset'], d['accessors'][0], d['scenes'][0])
        holder['extensions'] = {name: body}; d['extensionsUsed'] = [name]
    if v == 'asset':
        d['asset'] = {'version': pick('2.0', '2.1', '3.0', '1.0', '2', '2.0.0', '02.0'), 'minVersion': pick(None, '2.0', '2.1', '2.0.1', '1.0', '3.0')}
        if d['asset']['minVersion'] is None: del d['asset']['minVersion']
    if v == 'used_unused': d['extensionsUsed'] = [pick('KHR_materials_unlit', 'EXT_foo', 'KHR_mesh_quantization')]
    if v == 'empty_lists': d[pick('extensionsUsed', 'extensionsRequired')] = []
    return b.finish()


def shape_json_text():
    """JSON text the generator never writes: escaped and unicode keys, duplicate keys, non-UTF-8
    bytes, a BOM, -0 and huge exponents, deep nesting in extras, a very long array."""
    b = Builder(texture=False)
    doc, blob, _ = b.finish()
    text = dumps(doc)
    v = pick('escaped_key', 'dup_key', 'dup_key_inner', 'bad_utf8', 'bom', 'neg_zero', 'huge_exp', 'deep', 'unicode_name', 'lone_surrogate',
             'escaped_value', 'trailing')
    if v == 'escaped_key': text = text.replace('"asset"', pick('"\\u0061sset"', '"as\\u0073et"'), 1)
    if v == 'dup_key': text = text.replace('{"asset":', '{"scene":0,"asset":', 1)
    if v == 'dup_key_inner': text = text.replace('"mesh":0', '"mesh":0,"mesh":' + pick('0', '5', '"x"'), 1)
    if v == 'bad_utf8': return None, text.replace('"asset":{', '"asset":{"generator":"\xff\xfe",', 1).encode('utf-8').replace(b'\xc3\xbf\xc3\xbe', pick(b'\xff\xfe', b'\xc3', b'\xed\xa0\x80')), 'raw'
    if v == 'bom': return None, b'\xef\xbb\xbf' + text.encode(), 'raw'
    if v == 'neg_zero': text = text.replace('"mesh":0', '"mesh":' + pick('-0', '-0.0', '0e5', '0.0e-0'), 1)
    if v == 'huge_exp': text = text.replace('"scene":0', '"scene":' + pick('1e400', '-1e400', '1e-400', '9007199254740993', '1E1'), 1)
    if v == 'deep': text = text.replace('"asset":{', '"asset":{"extras":' + '[' * pick(100, 600) + ']' * 0, 1) if False else text.replace('"asset":{', '"asset":{"extras":{"a":' + '[' * 200 + ']' * 200 + '},', 1)
    if v == 'unicode_name': text = text.replace('"asset":{', '"asset":{"generator":"\u00e9\U0001F600",', 1)
    if v == 'lone_surrogate': text = text.replace('"asset":{', '"asset":{"generator":"\\ud800",', 1)
    if v == 'escaped_value': text = text.replace('"VEC3"', '"VEC\\u0033"', 1)
    if v == 'trailing': text = text + pick(' ', '\n\n', ' x', '{}', '\0')
    return None, text.encode('utf-8', 'surrogatepass'), 'raw'


SHAPES = {f.__name__[6:]: f for f in [shape_sparse, shape_material_ext, shape_texture_transform, shape_quantization, shape_compression,
                                       shape_images, shape_glb_buffers, shape_scenes_nodes, shape_cameras, shape_skins, shape_animation,
                                       shape_accessors, shape_lights_variants, shape_extension_lists, shape_json_text]}


# ---------------------------------------------------------------------------------------------
# Shapes of the second set (--shapes-set 2): features the first set reaches only by chance.
# A shape may name companion files beside its document: container ('gltf', {suffix: bytes}),
# written as gen/<shape>_NNNNN<suffix>, and '%BASE%' in the document's text becomes that name.
# ---------------------------------------------------------------------------------------------
def fresh(b):
    """Empties a Builder's binary, views and accessors (the primitive keeps its dict)."""
    b.blob = bytearray(); b.doc['bufferViews'] = []; b.doc['accessors'] = []
    b.prim()['attributes'] = {}; b.prim().pop('indices', None)


def shape_morph():
    """Morph targets: target attributes (POSITION, NORMAL, TANGENT, TEXCOORD/COLOR, names the base
    lacks or that are invalid), their formats, counts and bounds; mesh.weights and node.weights
    lengths against the target count; primitives with unequal target counts; empty targets."""
    b = Builder(texture=rng.random() < 0.3)
    p = b.prim()
    if rng.random() < 0.3: p['attributes']['TANGENT'] = b.acc('f', [1, 0, 0, 1] * 3, 5126, 'VEC4', 3, target=34962)
    def target():
        t = {}
        for sem in rng.sample(['POSITION', 'POSITION', 'NORMAL', 'TANGENT', 'TEXCOORD_0', 'COLOR_0', '_CUSTOM', 'JOINTS_0', 'position'], pick(1, 1, 2, 3)):
            kind = {'TANGENT': pick('VEC3', 'VEC3', 'VEC4'), 'TEXCOORD_0': 'VEC2', 'COLOR_0': pick('VEC3', 'VEC4'), 'JOINTS_0': 'VEC4'}.get(sem, pick('VEC3', 'VEC3', 'VEC3', 'VEC4', 'VEC2'))
            ct = pick(5126, 5126, 5126, 5120, 5122, 5121)
            n = pick(3, 3, 3, 3, 2, 4)
            vals = [pick(0, 0, 0.1, -0.5, 1) for _ in range(WIDTH[kind] * n)]
            if ct != 5126: vals = [int(v * (127 if ct == 5120 else 255 if ct == 5121 else 32767)) for v in vals]
            t[sem] = b.acc(FMT[ct], vals, ct, kind, n, target=pick(34962, 34962, None), minmax=sem != 'POSITION' or rng.random() < 0.8,
                           normalized=ct != 5126 and rng.random() < 0.7)
        return t
    nt = pick(1, 1, 2, 3, 0)
    p['targets'] = [target() if rng.random() < 0.9 else {} for _ in range(nt)]
    w = [0.5] * nt
    mw = pick('same', 'same', 'none', 'more', 'fewer', 'empty')
    if mw != 'none': b.doc['meshes'][0]['weights'] = {'same': w, 'more': w + [0], 'fewer': w[1:], 'empty': []}[mw]
    if rng.random() < 0.3: b.doc['nodes'][0]['weights'] = pick(w, w + [1], w[1:], [])
    if rng.random() < 0.2:
        second = copy.deepcopy(p)
        second['targets'] = second['targets'][:pick(0, 1, 2)] if rng.random() < 0.7 else second['targets']
        if not second['targets']: del second['targets']
        b.doc['meshes'][0]['primitives'].append(second)
    if rng.random() < 0.15:
        b.doc['nodes'].append({'weights': pick([0], w)}); b.doc['scenes'][0]['nodes'].append(1)
    return b.finish()


def shape_samplers():
    """Samplers and textures: filter and wrap values (valid, neighbours, strings, floats), a texture
    without a sampler or source, indices out of range, unused samplers, textures and images."""
    b = Builder()
    s = {}
    for k, vals in (('magFilter', [9728, 9729, 9984, 9987, 9986, 0, 9729.5, '9729']), ('minFilter', [9728, 9729, 9984, 9985, 9986, 9987, 9988, 10497]),
                    ('wrapS', [10497, 33071, 33648, 9729, 0, 33648.0]), ('wrapT', [10497, 33071, 33648, 33649, -1, None])):
        if rng.random() < 0.5: s[k] = rng.choice(vals)
    s = {k: v for k, v in s.items() if v is not None}
    if rng.random() < 0.1: s['name'] = pick('s', 1)
    b.doc['samplers'] = [s]
    tex = b.doc['textures'][0]
    v = pick('plain', 'plain', 'no_sampler', 'no_source', 'sampler_oob', 'source_oob', 'unused_sampler', 'unused_texture', 'unused_image', 'shared')
    if v == 'no_sampler': del tex['sampler']; b.doc.pop('samplers') if rng.random() < 0.7 else None
    if v == 'no_source': del tex['source']
    if v == 'sampler_oob': tex['sampler'] = pick(1, -1, 'x')
    if v == 'source_oob': tex['source'] = pick(1, -1, 1.5)
    if v == 'unused_sampler': b.doc['samplers'].append(pick({}, {'magFilter': 9728}))
    if v == 'unused_texture': b.doc['textures'].append({'source': 0, 'sampler': pick(0, 1)})
    if v == 'unused_image': b.doc['images'].append({'uri': b.doc['images'][0]['uri']})
    if v == 'shared':
        b.doc['materials'][0]['emissiveTexture'] = {'index': 0}; b.doc['materials'][0]['emissiveFactor'] = [1, 1, 1]
    return b.finish()


def shape_primitives():
    """Primitive modes against vertex and index counts, index values (out of range, primitive
    restart, degenerate triangles) in each index format, attribute names (sets that skip a number,
    lower case, custom, JOINTS without WEIGHTS) and primitives without POSITION or indices."""
    b = Builder(uv=False, normals=False, texture=False)
    fresh(b)
    p = b.prim()
    nv = pick(1, 2, 3, 4, 6)
    vals = [float(rng.randrange(3)) for _ in range(nv * 3)]
    p['attributes']['POSITION'] = b.acc('f', vals, 5126, 'VEC3', nv, target=34962, minmax=True)
    mode = pick(None, 0, 1, 2, 3, 4, 4, 5, 6, 7, -1)
    if mode is not None: p['mode'] = mode
    if rng.random() < 0.7:
        ct = pick(5121, 5123, 5123, 5125, 5122)
        n = pick(0, 1, 2, 3, 3, 4, 5, 6, 7)
        idx = [rng.randrange(nv) for _ in range(n)]
        if idx and rng.random() < 0.3: idx[rng.randrange(n)] = pick(nv, nv + 5, {5121: 255, 5123: 65535, 5125: 2 ** 32 - 1, 5122: 32767}[ct])
        if len(idx) >= 3 and rng.random() < 0.2: idx[1] = idx[0]
        p['indices'] = b.acc(FMT[ct], idx, ct, 'SCALAR', max(n, 1) if idx else pick(0, 1), target=pick(34963, 34963, None))
        if not idx: b.doc['bufferViews'].append({'buffer': 0, 'byteLength': 4}); b.doc['accessors'][-1]['bufferView'] = len(b.doc['bufferViews']) - 1
    extra = pick(None, None, 'TEXCOORD_1', 'COLOR_1', '_FOO', 'foo', 'TEXCOORD_01', 'JOINTS_0', 'TEXCOORD_0', 'COLOR_0', 'WEIGHTS_0', 'texcoord_0')
    if extra:
        kind = {'JOINTS_0': 'VEC4', 'WEIGHTS_0': 'VEC4', 'COLOR_0': 'VEC4', 'COLOR_1': 'VEC4'}.get(extra, 'VEC2')
        ct = 5121 if extra == 'JOINTS_0' else 5126
        p['attributes'][extra] = b.acc(FMT[ct], [0] * (WIDTH[kind] * nv), ct, kind, nv, target=34962)
    if rng.random() < 0.1: del p['attributes']['POSITION']
    if rng.random() < 0.15:
        b.doc['meshes'][0]['primitives'].append({'attributes': dict(p['attributes']), 'mode': pick(0, 1, 4)})
    return b.finish()


def shape_material_combos():
    """Core material values and the combinations the catalogue names: alphaCutoff against
    alphaMode, emissive strength with a zero or absent emissiveFactor, volume without transmission
    or on a double-sided material, dispersion without volume, iridescence thickness ranges,
    clearcoat or anisotropy texture sets against the normal texture's, unlit or specular-glossiness
    beside other extensions, normal maps and tangents (present, absent, unused)."""
    b = Builder()
    p = b.prim()
    m = b.doc['materials'][0]
    ext = m.setdefault('extensions', {})
    v = pick('alpha', 'emissive', 'volume', 'dispersion', 'iridescence', 'texcoords', 'multiple', 'tangent', 'factors')
    if v == 'alpha':
        m['alphaMode'] = pick('OPAQUE', 'MASK', 'BLEND', 'mask', None)
        if m['alphaMode'] is None: del m['alphaMode']
        if rng.random() < 0.7: m['alphaCutoff'] = pick(0.5, 0, 1, -0.1, 2)
    if v == 'emissive':
        ext['KHR_materials_emissive_strength'] = {'emissiveStrength': pick(0, 1, 2, -1)} if rng.random() < 0.9 else {}
        f = pick(None, [0, 0, 0], [1, 1, 1], [0, 0, 0.5])
        if f is not None: m['emissiveFactor'] = f
        if rng.random() < 0.3: m['emissiveTexture'] = {'index': 0}
    if v == 'volume':
        ext['KHR_materials_volume'] = {'thicknessFactor': pick(0, 0.5, 1), 'attenuationDistance': pick(1, 0, -1, None)}
        if ext['KHR_materials_volume']['attenuationDistance'] is None: del ext['KHR_materials_volume']['attenuationDistance']
        if rng.random() < 0.5: ext['KHR_materials_transmission'] = {'transmissionFactor': pick(0, 1)}
        if rng.random() < 0.4: m['doubleSided'] = pick(True, False)
    if v == 'dispersion':
        ext['KHR_materials_dispersion'] = {'dispersion': pick(0, 0.1, -1, 20)}
        if rng.random() < 0.5: ext['KHR_materials_volume'] = {'thicknessFactor': pick(0, 1)}
        if rng.random() < 0.5: ext['KHR_materials_transmission'] = {}
    if v == 'iridescence':
        ir = {'iridescenceFactor': pick(0, 1)}
        for k in ('iridescenceThicknessMinimum', 'iridescenceThicknessMaximum'):
            if rng.random() < 0.6: ir[k] = pick(0, 100, 400, -1)
        if rng.random() < 0.5: ir['iridescenceThicknessTexture'] = {'index': 0}
        if rng.random() < 0.2: ir['iridescenceIor'] = pick(1, 0.5, 1.3)
        ext['KHR_materials_iridescence'] = ir
    if v == 'texcoords':
        p['attributes']['TEXCOORD_1'] = b.acc('f', [0, 0, 1, 0, 0, 1], 5126, 'VEC2', 3, target=34962)
        m['normalTexture'] = {'index': 0, 'texCoord': pick(0, 1)}
        if rng.random() < 0.5: ext['KHR_materials_clearcoat'] = {'clearcoatNormalTexture': {'index': 0, 'texCoord': pick(0, 1)}}
        else: ext['KHR_materials_anisotropy'] = {'anisotropyTexture': {'index': 0, 'texCoord': pick(0, 1)}}
        if rng.random() < 0.5: p['attributes']['TANGENT'] = b.acc('f', [1, 0, 0, 1] * 3, 5126, 'VEC4', 3, target=34962)
    if v == 'multiple':
        first = pick('KHR_materials_unlit', 'KHR_materials_pbrSpecularGlossiness')
        ext[first] = {}
        for name in rng.sample(['KHR_materials_clearcoat', 'KHR_materials_sheen', 'KHR_materials_ior', 'KHR_materials_emissive_strength',
                                'KHR_materials_unlit', 'KHR_materials_specular', 'KHR_materials_transmission'], pick(1, 2)):
            ext[name] = {}
    if v == 'tangent':
        if rng.random() < 0.6: m['normalTexture'] = {'index': 0}
        if rng.random() < 0.5: p['attributes']['TANGENT'] = b.acc('f', [1, 0, 0, pick(1, -1, 0)] * 3, 5126, 'VEC4', 3, target=34962)
        if rng.random() < 0.3: del p['attributes']['NORMAL']
        if rng.random() < 0.3: ext['KHR_materials_anisotropy'] = {'anisotropyStrength': pick(0, 0.5)}
    if v == 'factors':
        pbr = m['pbrMetallicRoughness']
        k = pick('baseColorFactor', 'metallicFactor', 'roughnessFactor', 'emissiveFactor', 'normalScale', 'occlusionStrength')
        val = {'baseColorFactor': pick([1, 1, 1, 1], [2, 0, 0, 1], [-0.1, 0, 0, 1], [1, 1, 1], [1, 1, 1, 1, 1]),
               'emissiveFactor': pick([1.5, 0, 0], [-1, 0, 0], [1, 1])}.get(k, pick(0, 1, 1.5, -0.5))
        if k in ('baseColorFactor', 'metallicFactor', 'roughnessFactor'): pbr[k] = val
        elif k == 'emissiveFactor': m[k] = val
        elif k == 'normalScale': m['normalTexture'] = {'index': 0, 'scale': val}
        else: m['occlusionTexture'] = {'index': 0, 'strength': val}
    if not ext: del m['extensions']
    for name in ext:
        if rng.random() < 0.9: b.use(name)
    return b.finish()


def shape_uris_extras():
    """External resources beside the document (present, missing, shorter or longer than declared,
    names with spaces, percent escapes, queries, fragments, backslashes, absolute and remote URIs),
    extras and unknown members on every kind of object, names of the wrong type, asset members,
    and unsupported extensions (EXT_mesh_gpu_instancing, KHR_xmp_json_ld) that name other objects."""
    b = Builder()
    doc, blob, _ = b.finish()
    files = {}
    v = pick('buffer', 'buffer', 'image', 'extras', 'extras', 'asset', 'unsupported')
    if v == 'buffer':
        how = pick('ok', 'short', 'long', 'missing', 'space', 'percent', 'query', 'fragment', 'backslash', 'remote', 'absolute', 'upper')
        name = {'space': '%BASE% data.bin', 'upper': '%BASE%.BIN'}.get(how, '%BASE%.bin')
        uri = {'percent': '%BASE%%20data.bin', 'query': '%BASE%.bin?x=1', 'fragment': '%BASE%.bin#frag', 'backslash': '.\\%BASE%.bin',
               'remote': 'http://example.com/%BASE%.bin', 'absolute': '/%BASE%.bin', 'missing': '%BASE%_missing.bin'}.get(how, name)
        if how == 'percent': name = '%BASE% data.bin'
        data = blob[:-4] if how == 'short' else blob + b'\0' * 8 if how == 'long' else blob
        files[name[len('%BASE%'):]] = data
        doc['buffers'][0]['uri'] = uri
    if v == 'image':
        how = pick('ok', 'missing', 'jpeg_named_png', 'mime', 'space', 'junk')
        data = png(1, 1, (1, 2, 3, 255)) if how != 'jpeg_named_png' else b'\xff\xd8\xff\xe0\0\x10JFIF\0' + b'\0' * 8
        if how == 'junk': data = b'not an image'
        name = '%BASE% a.png' if how == 'space' else '%BASE%.png'
        files[name[len('%BASE%'):]] = data
        img = {'uri': {'missing': '%BASE%_missing.png', 'space': pick('%BASE% a.png', '%BASE%%20a.png')}.get(how, name)}
        if how == 'mime' or rng.random() < 0.2: img['mimeType'] = pick('image/png', 'image/jpeg', 'image/gif')
        doc['images'] = [img]
    if v == 'extras':
        holders = [doc, doc['asset'], doc['nodes'][0], doc['meshes'][0], doc['meshes'][0]['primitives'][0], doc['accessors'][0],
                   doc['bufferViews'][0], doc['buffers'][0], doc['materials'][0], doc['materials'][0]['pbrMetallicRoughness'],
                   doc['materials'][0]['pbrMetallicRoughness']['baseColorTexture'], doc['textures'][0], doc['images'][0],
                   doc['samplers'][0], doc['scenes'][0], doc['meshes'][0]['primitives'][0]['attributes']]
        for holder in rng.sample(holders, pick(1, 1, 2)):
            k = pick('extras', 'extras', 'foo', 'name', 'extensions')
            holder[k] = {'extras': pick({}, {'a': 1}, 1, 'x', [], None, True), 'foo': pick(1, {}), 'name': pick('n', 1, None, ['n']),
                         'extensions': pick({}, [], 1, {'foo': {}})}[k]
    if v == 'asset':
        a = doc['asset']
        k = pick('generator', 'copyright', 'minVersion', 'version', 'foo', 'extensions')
        a[k] = {'generator': pick('g', 1, None), 'copyright': pick('c', 1, ['c']), 'minVersion': pick('2.0', '2.0.0', '1.9', '', 2.0),
                'version': pick('2.0', '2.00', '2.0 ', ' 2.0', '2.x', 'v2.0', '2.0.1', 2.0, '20', '2.', '.0'), 'foo': 1,
                'extensions': pick({}, {'EXT_foo': {}})}[k]
        if k == 'version' and rng.random() < 0.3: a['minVersion'] = pick('2.0', '2.1')
    if v == 'unsupported':
        name = pick('EXT_mesh_gpu_instancing', 'KHR_xmp_json_ld')
        if name == 'EXT_mesh_gpu_instancing':
            doc['bufferViews'].append({'buffer': 0, 'byteOffset': 0, 'byteLength': 24})
            doc['accessors'].append({'bufferView': len(doc['bufferViews']) - 1, 'componentType': 5126, 'count': 2, 'type': 'VEC3'})
            doc['nodes'][0]['extensions'] = {name: {'attributes': {'TRANSLATION': len(doc['accessors']) - pick(1, 1, 0)}}}
        else:
            doc['extensions'] = {name: {'packets': pick([{}], [{'@context': {}}], [], [1])}}
            pick(doc['asset'], doc['nodes'][0], doc['materials'][0])['extensions'] = {name: {'packet': pick(0, 0, 1, -1)}}
        if rng.random() < 0.9: doc['extensionsUsed'] = [name]
        if rng.random() < 0.2: doc['extensionsRequired'] = [name]
    return doc, blob, ('gltf', files)


def shape_accessor_bounds():
    """Accessor min and max on every component type and element type, normalized or not: exact
    bounds, bounds written in the normalized range, rounded floats (0.1), -0, one unit off, min
    above max, on an attribute of its own (a custom semantic, so no format rule applies) or unused."""
    b = Builder(texture=False)
    ct = pick(5120, 5121, 5122, 5123, 5125, 5126, 5126)
    kind = pick('SCALAR', 'VEC2', 'VEC3', 'VEC4')
    w = WIDTH[kind]
    norm = ct not in (5125, 5126) and rng.random() < 0.5
    top = {5120: 127, 5121: 255, 5122: 32767, 5123: 65535, 5125: 2 ** 32 - 1}.get(ct)
    if ct == 5126: vals = [pick(0.1, -0.0, 0.0, 1.5, -2.25, 1e30, 3.4028234663852886e38, 1e-40) for _ in range(3 * w)]
    else: vals = [pick(0, 1, top, -top - 1 if ct in (5120, 5122) else 0, top // 2) for _ in range(3 * w)]
    a = b.acc(FMT[ct], vals, ct, kind, 3, target=34962, normalized=norm)
    acc = b.doc['accessors'][a]
    packed = struct.unpack('<' + FMT[ct] * len(vals), pack(FMT[ct], vals))
    lo = [min(packed[i::w]) for i in range(w)]; hi = [max(packed[i::w]) for i in range(w)]
    form = pick('exact', 'exact', 'written', 'normalized', 'off', 'swapped', 'float_form', 'one_only')
    if form == 'written': lo = [min(vals[i::w]) for i in range(w)]; hi = [max(vals[i::w]) for i in range(w)]
    if form == 'normalized' and top: lo = [x / top for x in lo]; hi = [x / top for x in hi]
    if form == 'off': i = rng.randrange(w); (lo if rng.random() < 0.5 else hi)[i] += pick(1, -1, 0.5, 1e-7)
    if form == 'swapped': lo, hi = hi, lo
    if form == 'float_form': lo = [Num('%r' % float(x)) for x in lo]; hi = [Num('%.1f' % x) for x in hi]
    acc['min'] = lo; acc['max'] = hi
    if form == 'one_only': del acc[pick('min', 'max')]
    if rng.random() < 0.75: b.prim()['attributes'][pick('_DATA', '_DATA', 'TEXCOORD_0', 'COLOR_0')] = a
    return b.finish()


def shape_buffer_views():
    """byteStride rules: two accessors in one view (interleaved with a stride, or without one),
    strides below 4, above 252, not a multiple of 4 or beyond the view, views that fit their last
    element exactly or miss it by one byte, a vertex view with an index target, unused views and
    buffers, empty views."""
    b = Builder(uv=False, normals=False, texture=False)
    fresh(b)
    p = b.prim()
    n = 3
    pos = [0, 0, 0, 1, 0, 0, 0, 1, 0]
    nrm = [0, 0, 1] * 3
    v = pick('interleaved', 'interleaved', 'shared_no_stride', 'stride', 'fit', 'target', 'unused', 'empty')
    if v in ('interleaved', 'shared_no_stride'):
        data = b''.join(struct.pack('<3f', *pos[3 * i:3 * i + 3]) + struct.pack('<3f', *nrm[3 * i:3 * i + 3]) for i in range(n))
        stride = None if v == 'shared_no_stride' else pick(24, 24, 20, 28, 32, 12)
        view = b.view(data + b'\0' * pick(0, 0, 8), target=34962, stride=stride)
        p['attributes']['POSITION'] = len(b.doc['accessors'])
        b.doc['accessors'].append({'bufferView': view, 'componentType': 5126, 'count': n, 'type': 'VEC3', 'min': [0, 0, 0], 'max': [1, 1, 0]})
        p['attributes']['NORMAL'] = len(b.doc['accessors'])
        b.doc['accessors'].append({'bufferView': view, 'byteOffset': pick(12, 12, 16, 24), 'componentType': 5126, 'count': n, 'type': 'VEC3'})
    else:
        stride = pick(None, 12, 16, 4, 2, 6, 13, 252, 256, 40)
        p['attributes']['POSITION'] = b.acc('f', pos, 5126, 'VEC3', n, target=pick(34962, 34962, 34963, None), minmax=True)
        view = b.doc['bufferViews'][-1]
        if v == 'stride' and stride: view['byteStride'] = stride
        if v == 'fit':
            view['byteStride'] = pick(16, 20, 24)
            view['byteLength'] = view['byteStride'] * (n - 1) + 12 + pick(0, -1, -4, 4)
            b.blob.extend(b'\0' * 64)
        if v == 'unused': b.doc['bufferViews'].append({'buffer': 0, 'byteLength': pick(4, 12), 'byteStride': pick(None, 4)}); b.doc['bufferViews'][-1] = {k: x for k, x in b.doc['bufferViews'][-1].items() if x is not None}
        if v == 'empty': b.doc['bufferViews'].append({'buffer': 0, 'byteLength': pick(0, 1)})
        if v == 'target': view['target'] = pick(34963, 34962, 1, 0)
    p['indices'] = b.acc('H', [0, 1, 2], 5123, 'SCALAR', 3, target=34963)
    doc, blob, c = b.finish()
    if v == 'unused' and rng.random() < 0.5: doc['buffers'].append({'byteLength': pick(0, 4), 'uri': data_uri(b'\0' * 4)})
    return doc, blob, c


def shape_anim_samplers():
    """Animation samplers and channels as objects: several samplers, unused ones, two channels on
    one sampler, sampler indices out of range, empty channel or sampler lists, input and output
    accessors shared or of other formats (normalized, integer), CUBICSPLINE with two or one key."""
    b = Builder(texture=False)
    b.doc['nodes'].append({}); b.doc['scenes'][0]['nodes'].append(1)
    keys = pick(1, 2, 2, 3)
    ict = pick(5126, 5126, 5126, 5121, 5123)
    times = [float(i) for i in range(keys)] if ict == 5126 else list(range(keys))
    inp = b.acc(FMT[ict], times, ict, 'SCALAR', keys, minmax=True, normalized=ict != 5126 and rng.random() < 0.7)
    samplers, channels = [], []
    for i, path in enumerate(rng.sample(['translation', 'rotation', 'scale'], pick(1, 2, 3))):
        interp = pick(None, 'LINEAR', 'STEP', 'CUBICSPLINE')
        k = 'VEC4' if path == 'rotation' else 'VEC3'
        oct_ = pick(5126, 5126, 5126, 5122, 5120) if path == 'rotation' else 5126
        cnt = keys * (3 if interp == 'CUBICSPLINE' else 1)
        vals = ([0, 0, 0, 1] if k == 'VEC4' else [1, 1, 1]) * cnt
        if oct_ != 5126: vals = [int(x * (127 if oct_ == 5120 else 32767)) for x in vals]
        out = b.acc(FMT[oct_], vals, oct_, k, cnt, normalized=oct_ != 5126 and rng.random() < 0.8)
        s = {'input': inp, 'output': out}
        if interp: s['interpolation'] = interp
        samplers.append(s)
        channels.append({'sampler': i, 'target': {'node': pick(0, 1), 'path': path}})
    v = pick('plain', 'unused_sampler', 'shared_sampler', 'sampler_oob', 'no_channels', 'no_samplers', 'two_animations', 'output_as_input')
    if v == 'unused_sampler': samplers.append(copy.deepcopy(samplers[0]))
    if v == 'shared_sampler': channels.append({'sampler': 0, 'target': {'node': 1 - channels[0]['target']['node'], 'path': channels[0]['target']['path']}})
    if v == 'sampler_oob': channels[-1]['sampler'] = pick(len(samplers), -1)
    if v == 'no_channels': channels = []
    if v == 'no_samplers': samplers = []
    if v == 'output_as_input': samplers[0]['output'] = inp
    b.doc['animations'] = [{'samplers': samplers, 'channels': channels}]
    if v == 'two_animations': b.doc['animations'].append(copy.deepcopy(b.doc['animations'][0]))
    return b.finish()


SHAPES2 = {f.__name__[6:]: f for f in [shape_morph, shape_samplers, shape_primitives, shape_material_combos, shape_uris_extras,
                                        shape_accessor_bounds, shape_buffer_views, shape_anim_samplers]}


# ---------------------------------------------------------------------------------------------
# Shapes of the third set (--shapes-set 3): features neither set above varies on purpose.
# ---------------------------------------------------------------------------------------------
IDENT = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]


def shape_attributes():
    """Vertex attribute semantics and their formats without KHR_mesh_quantization: several
    TEXCOORD/COLOR/JOINTS/WEIGHTS sets numbered with gaps or from 1, custom _NAMES of any format
    (UNSIGNED_INT, matrices), per-semantic type/componentType/normalized combinations, POSITION
    bounds present, partial or absent, and attribute offsets that break the 4-byte alignment."""
    b = Builder(uv=False, normals=rng.random() < 0.6, texture=False)
    p = b.prim()
    forms = {'TEXCOORD': [(5126, 'VEC2', False), (5121, 'VEC2', True), (5123, 'VEC2', True), (5121, 'VEC2', False), (5126, 'VEC3', False), (5120, 'VEC2', True)],
             'COLOR': [(5126, 'VEC3', False), (5126, 'VEC4', False), (5121, 'VEC4', True), (5123, 'VEC3', True), (5121, 'VEC4', False), (5126, 'VEC2', False), (5122, 'VEC4', True)],
             'JOINTS': [(5121, 'VEC4', False), (5123, 'VEC4', False), (5126, 'VEC4', False), (5121, 'VEC3', False), (5121, 'VEC4', True)],
             'WEIGHTS': [(5126, 'VEC4', False), (5121, 'VEC4', True), (5123, 'VEC4', True), (5121, 'VEC4', False), (5126, 'VEC3', False)],
             '_': [(5125, 'SCALAR', False), (5126, 'MAT4', False), (5121, 'VEC3', False), (5122, 'VEC2', True), (5126, 'SCALAR', False), (5126, 'VEC4', True)]}
    for base in rng.sample(['TEXCOORD', 'COLOR', 'JOINTS', 'WEIGHTS', '_'], pick(1, 2, 2, 3)):
        sets = pick([0], [0, 1], [0, 2], [1], [0, 1, 2], [0, 1, 3], [0, 0])
        for i in sets:
            name = '_%s' % pick('FOO', 'BAR_%d' % i, 'foo', 'ID') if base == '_' else '%s_%d' % (base, i)
            ct, kind, norm = pick(*forms[base])
            w = WIDTH[kind]
            if ct == 5126: vals = [pick(0.0, 0.25, 0.5, 1.0) for _ in range(3 * w)]
            else: vals = [pick(0, 1, 2) for _ in range(3 * w)]
            if base == 'WEIGHTS' and ct == 5126 and kind == 'VEC4': vals = pick([1, 0, 0, 0], [0.5, 0.5, 0, 0]) * 3
            if base == 'WEIGHTS' and ct != 5126 and kind == 'VEC4': vals = [255 if ct == 5121 else 65535, 0, 0, 0] * 3
            stride = pick(None, None, None, 4 * ((SIZE[ct] * w + 3) // 4) + pick(0, 4))
            v = b.view(pack(FMT[ct], vals), target=pick(34962, 34962, 34962, None), stride=stride)
            a = {'bufferView': v, 'componentType': ct, 'count': 3, 'type': kind}
            if norm: a['normalized'] = True
            if rng.random() < 0.15: a['normalized'] = pick(False, True)
            if rng.random() < 0.1 and SIZE[ct] * w % 4:
                a['byteOffset'] = SIZE[ct]; b.doc['bufferViews'][v]['byteLength'] += 4 * SIZE[ct] * w
                b.blob.extend(b'\0' * (4 * SIZE[ct] * w))
            if rng.random() < 0.2: a['min'] = [min(vals[j::w]) for j in range(w)]; a['max'] = [max(vals[j::w]) for j in range(w)]
            b.doc['accessors'].append(a)
            p['attributes'][name] = len(b.doc['accessors']) - 1
    if ('JOINTS_0' in p['attributes'] or 'WEIGHTS_0' in p['attributes']) and rng.random() < 0.7:
        b.doc['nodes'] = [{'mesh': 0, 'skin': 0}, {}]; b.doc['scenes'][0]['nodes'] = [0, 1]; b.doc['skins'] = [{'joints': [1]}]
    pos = b.doc['accessors'][p['attributes']['POSITION']]
    bounds = pick('both', 'both', 'none', 'min', 'max', 'short')
    if bounds == 'none': del pos['min'], pos['max']
    if bounds in ('min', 'max'): del pos[bounds]
    if bounds == 'short': pos['min'] = pos['min'][:2]
    return b.finish()


def shape_indices():
    """Index accessors: every component type and element type, normalized, with a byteStride, a
    byteOffset off the component size, views without a target or an ARRAY_BUFFER target, the same
    index accessor in two primitives with different vertex counts, as an attribute or animation
    input as well, declared bounds, and restart/out-of-range/degenerate values per mode."""
    b = Builder(uv=False, normals=False, texture=False)
    fresh(b)
    p = b.prim()
    nv = pick(3, 4, 6)
    p['attributes']['POSITION'] = b.acc('f', [float(rng.randrange(4)) for _ in range(nv * 3)], 5126, 'VEC3', nv, target=34962, minmax=True)
    ct = pick(5121, 5123, 5125, 5125, 5123, 5120, 5122, 5126)
    kind = pick('SCALAR', 'SCALAR', 'SCALAR', 'SCALAR', 'VEC2', 'VEC3')
    mode = pick(None, 4, 4, 5, 6, 1, 2, 3, 0)
    n = pick(3, 4, 5, 6, 7, 8)
    idx = [rng.randrange(nv) for _ in range(n * WIDTH[kind])]
    top = {5121: 255, 5123: 65535, 5125: 2 ** 32 - 1, 5120: 127, 5122: 32767, 5126: 0}[ct]
    twist = pick('plain', 'plain', 'restart', 'oob', 'degenerate', 'all_degenerate', 'strip_degenerate')
    if twist == 'restart': idx[rng.randrange(len(idx))] = top
    if twist == 'oob': idx[rng.randrange(len(idx))] = pick(nv, nv + 1, top - 1)
    if twist == 'degenerate' and len(idx) >= 3: idx[1] = idx[0]
    if twist == 'all_degenerate': idx = [0] * len(idx)
    if twist == 'strip_degenerate': idx = ([0, 1, 2, 2, 3, 3] + [1] * 10)[:len(idx)]
    a = b.acc(FMT[ct], idx, ct, kind, n, target=pick(34963, 34963, 34963, None, 34962), minmax=rng.random() < 0.2)
    acc = b.doc['accessors'][a]
    if rng.random() < 0.1: acc['normalized'] = True
    if rng.random() < 0.1: b.doc['bufferViews'][acc['bufferView']]['byteStride'] = pick(2, 4, 8)
    if rng.random() < 0.1 and SIZE[ct] > 1:
        acc['byteOffset'] = pick(1, SIZE[ct] + 1, SIZE[ct]); b.doc['bufferViews'][acc['bufferView']]['byteLength'] += 8; b.blob.extend(b'\0' * 8)
    p['indices'] = a
    if mode is not None: p['mode'] = mode
    use = pick('one', 'one', 'one', 'two_prims', 'as_attribute', 'as_input')
    if use == 'two_prims':
        b.doc['meshes'][0]['primitives'].append({'attributes': {'POSITION': b.acc('f', [0, 0, 0, 1, 0, 0, 0, 1, 0], 5126, 'VEC3', 3, target=34962, minmax=True)},
                                                  'indices': a, 'mode': pick(4, 0, 1)})
    if use == 'as_attribute': p['attributes']['_IDX'] = a
    if use == 'as_input':
        out = b.acc('f', [0.0] * (3 * n), 5126, 'VEC3', n)
        b.doc['animations'] = [{'samplers': [{'input': a, 'output': out}], 'channels': [{'sampler': 0, 'target': {'node': 0, 'path': 'translation'}}]}]
    return b.finish()


def shape_skin_details():
    """Skins in detail: two skins sharing joints, skeleton a joint itself, an ancestor, a descendant
    or a node of another tree, joints at different depths and in other scenes, IBM accessors
    (count, type, normalized, stride, sparse, last row not 0 0 0 1), a skinned mesh used by a node
    without a skin, a skin on a node whose mesh has no JOINTS, two JOINTS/WEIGHTS sets."""
    b = Builder(texture=False)
    p = b.prim()
    nsets = pick(1, 1, 1, 2)
    for s in range(nsets):
        jv = pick([0, 1, 0, 0], [0, 1, 2, 3], [3, 0, 0, 0], [0, 0, 0, 0], [4, 1, 0, 0])
        wv = pick([0.5, 0.5, 0, 0], [1, 0, 0, 0], [0.25, 0.25, 0.25, 0.25], [0, 0, 0, 0], [0.5, 0, 0, 0])
        p['attributes']['JOINTS_%d' % s] = b.acc('B', jv * 3, 5121, 'VEC4', 3, target=34962)
        p['attributes']['WEIGHTS_%d' % s] = b.acc('f', wv * 3, 5126, 'VEC4', 3, target=34962)
    # 0: skinned node; 1 root -> 2 -> 3 joints chain; 4 another root; 5 child of 4
    nodes = [{'mesh': 0, 'skin': 0}, {'children': [2]}, {'children': [3]}, {}, {'children': [5]}, {}]
    joints = pick([1, 2, 3], [2, 3], [3], [1, 3], [2, 5], [3, 1, 2], [1, 2, 3, 4], [0, 1])
    skin = {'joints': list(joints)}
    sk = pick(None, None, 1, 2, 3, 4, 0, 5)
    if sk is not None: skin['skeleton'] = sk
    if rng.random() < 0.5:
        n = len(joints) + pick(0, 0, 0, 1, -1)
        ct, t = pick((5126, 'MAT4'), (5126, 'MAT4'), (5126, 'MAT4'), (5126, 'MAT3'), (5121, 'MAT4'), (5126, 'VEC4'))
        vals = (IDENT if t == 'MAT4' else [1] * WIDTH[t]) * max(n, 1)
        bad = pick(None, None, 3, 15, 12)
        if bad is not None and t == 'MAT4': vals = list(vals); vals[bad] = pick(1, 0.5, 2)
        a = b.acc(FMT[ct], vals, ct, t, max(n, 1), normalized=ct != 5126 and rng.random() < 0.5)
        if rng.random() < 0.1: b.doc['bufferViews'][-1]['byteStride'] = 64
        if rng.random() < 0.1: b.doc['bufferViews'][-1]['target'] = 34962
        skin['inverseBindMatrices'] = a
    skins = [skin]
    scenes = [{'nodes': [0, 1, 4]}]
    v = pick('plain', 'plain', 'second_skin', 'unskinned_user', 'skin_no_joints_mesh', 'joint_other_scene', 'node_transform', 'parent_transform')
    if v == 'second_skin':
        skins.append({'joints': pick([1, 2], list(joints), [4, 5])}); nodes.append({'mesh': 0, 'skin': 1}); scenes[0]['nodes'].append(6)
    if v == 'unskinned_user': nodes.append({'mesh': 0}); scenes[0]['nodes'].append(6)
    if v == 'skin_no_joints_mesh':
        b.doc['meshes'].append({'primitives': [{'attributes': {'POSITION': p['attributes']['POSITION']}}]}); nodes.append({'mesh': 1, 'skin': 0}); scenes[0]['nodes'].append(6)
    if v == 'joint_other_scene': scenes = [{'nodes': [0]}, {'nodes': [1, 4]}]
    if v == 'node_transform': nodes[0][pick('translation', 'scale', 'matrix')] = {'translation': [1, 0, 0], 'scale': [2, 2, 2], 'matrix': IDENT}.get(pick('translation', 'scale', 'matrix'), [1, 0, 0])
    if v == 'parent_transform': nodes[4]['children'] = [5, 0]; nodes[4]['translation'] = [0, 1, 0]; scenes[0]['nodes'] = [1, 4]
    b.doc['nodes'] = nodes; b.doc['skins'] = skins; b.doc['scenes'] = scenes
    if rng.random() < 0.2: b.doc['scene'] = len(scenes) - 1
    return b.finish()


def shape_anim_channels():
    """Animation channels: no target node, a node out of range, weights on meshes with 1-3 morph
    targets (output counts per target, CUBICSPLINE tripling, one key), weights on a node without a
    mesh or with a mesh without targets, several paths on one node, the same target in two
    animations or twice in one, channels on joints, matrix nodes or skinned nodes, input bounds
    that do not match the data, integer normalized weights outputs."""
    b = Builder(texture=False)
    nt = pick(0, 1, 2, 3)
    if nt:
        b.prim()['targets'] = [{'POSITION': b.acc('f', [0, 0, 1] * 3, 5126, 'VEC3', 3, target=34962, minmax=True)} for _ in range(nt)]
    b.doc['nodes'].append({}); b.doc['scenes'][0]['nodes'].append(1)
    anims = [{'samplers': [], 'channels': []}]
    for c in range(pick(1, 2, 3)):
        path = pick('weights', 'weights', 'translation', 'rotation', 'scale')
        node = pick(0, 0, 0, 1, 2, None)
        interp = pick(None, 'LINEAR', 'STEP', 'CUBICSPLINE')
        keys = pick(1, 2, 3)
        times = [float(i) for i in range(keys)]
        inp = b.acc('f', times, 5126, 'SCALAR', keys)
        ia = b.doc['accessors'][inp]
        bounds = pick('exact', 'exact', 'exact', 'none', 'wrong', 'min_only')
        if bounds == 'exact': ia['min'] = [times[0]]; ia['max'] = [times[-1]]
        if bounds == 'wrong': ia['min'] = [0.0]; ia['max'] = [times[-1] + pick(1, 0.5)]
        if bounds == 'min_only': ia['min'] = [0.0]
        k = {'weights': 'SCALAR', 'rotation': 'VEC4', 'translation': 'VEC3', 'scale': 'VEC3'}[path]
        per = max(nt, 1) if path == 'weights' else 1
        count = keys * per * (3 if interp == 'CUBICSPLINE' else 1) + pick(0, 0, 0, 0, per, -1)
        oct_ = pick(5126, 5126, 5126, 5121, 5120, 5123) if path == 'weights' else 5126
        vals = ([0, 0, 0, 1] if k == 'VEC4' else [0] * WIDTH[k]) * max(count, 1)
        out = b.acc(FMT[oct_], vals, oct_, k, max(count, 1), normalized=oct_ != 5126 and rng.random() < 0.8)
        s = {'input': inp, 'output': out}
        if interp: s['interpolation'] = interp
        anims[0]['samplers'].append(s)
        t = {'path': path}
        if node is not None: t['node'] = node
        anims[0]['channels'].append({'sampler': c, 'target': t})
    v = pick('plain', 'plain', 'dup_in_anim', 'dup_across', 'matrix_node', 'skinned', 'mesh_weights', 'node_weights')
    if v == 'dup_in_anim': anims[0]['channels'].append(copy.deepcopy(anims[0]['channels'][0]))
    if v == 'dup_across': anims.append(copy.deepcopy(anims[0]))
    if v == 'matrix_node': b.doc['nodes'][0]['matrix'] = pick(IDENT, [2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 1])
    if v == 'skinned':
        p = b.prim()
        p['attributes']['JOINTS_0'] = b.acc('B', [0, 0, 0, 0] * 3, 5121, 'VEC4', 3, target=34962)
        p['attributes']['WEIGHTS_0'] = b.acc('f', [1, 0, 0, 0] * 3, 5126, 'VEC4', 3, target=34962)
        b.doc['nodes'][0]['skin'] = 0; b.doc['skins'] = [{'joints': [1]}]
    if v == 'mesh_weights': b.doc['meshes'][0]['weights'] = [0.5] * nt if nt else [0.5]
    if v == 'node_weights': b.doc['nodes'][0]['weights'] = [0.5] * pick(nt, nt + 1)
    b.doc['animations'] = anims
    return b.finish()


def shape_instancing():
    """EXT_mesh_gpu_instancing: TRANSLATION/ROTATION/SCALE and custom attributes of several
    formats and counts, on a node with or without a mesh, declared, required or not, with bounds
    and targets; the accessors are otherwise unused."""
    b = Builder(texture=False)
    n = pick(2, 3)
    attrs = {}
    for name in rng.sample(['TRANSLATION', 'ROTATION', 'SCALE', '_ID', 'translation'], pick(1, 2, 3)):
        ct, kind = {'TRANSLATION': pick((5126, 'VEC3'), (5126, 'VEC3'), (5122, 'VEC3'), (5126, 'VEC4')),
                    'ROTATION': pick((5126, 'VEC4'), (5126, 'VEC4'), (5120, 'VEC4'), (5122, 'VEC4'), (5126, 'VEC3')),
                    'SCALE': pick((5126, 'VEC3'), (5126, 'VEC3'), (5121, 'VEC3')), '_ID': pick((5126, 'SCALAR'), (5125, 'SCALAR')),
                    'translation': (5126, 'VEC3')}[name]
        cnt = n + pick(0, 0, 0, 1)
        vals = ([0, 0, 0, 1] if kind == 'VEC4' else [1] * WIDTH[kind]) * cnt
        if ct in (5120, 5122) and kind == 'VEC4': vals = [0, 0, 0, 127 if ct == 5120 else 32767] * cnt
        if name == 'ROTATION' and rng.random() < 0.2: vals[0] = 1
        attrs[name] = b.acc(FMT[ct], vals, ct, kind, cnt, target=pick(None, None, 34962), minmax=rng.random() < 0.3,
                            normalized=ct in (5120, 5121, 5122) and rng.random() < 0.8)
    node = pick(0, 0, 1)
    if node == 1: b.doc['nodes'].append({}); b.doc['scenes'][0]['nodes'].append(1)
    ext = {'attributes': attrs} if rng.random() < 0.9 else pick({}, {'attributes': {}})
    b.doc['nodes'][node]['extensions'] = {'EXT_mesh_gpu_instancing': ext}
    if rng.random() < 0.85: b.use('EXT_mesh_gpu_instancing', required=rng.random() < 0.3)
    return b.finish()


def shape_variants():
    """KHR_materials_variants in detail: variants without names, with duplicate names or extra
    members, empty lists; mappings with materials or variants out of range, a variant in two
    mappings, empty variant lists, no material, names; mappings on several primitives, the root
    object missing or not declared, unused variants and materials."""
    b = Builder()
    b.doc['materials'].append({'name': 'm1'})
    variants = [{'name': 'a'}, {'name': 'b'}, {'name': 'c'}][:pick(1, 2, 3)]
    vv = pick('plain', 'plain', 'no_name', 'dup_name', 'extra', 'empty', 'missing_root')
    if vv == 'no_name': variants[0] = {}
    if vv == 'dup_name' and len(variants) > 1: variants[1]['name'] = 'a'
    if vv == 'extra': variants[0]['extras'] = pick({}, 1); variants[0]['foo'] = 1
    if vv == 'empty': variants = []
    if vv != 'missing_root': b.doc['extensions'] = {'KHR_materials_variants': {'variants': variants}}
    nv = max(len(variants), 1)
    maps = []
    for _ in range(pick(1, 2, 3)):
        m = {'material': pick(0, 1, 1, 2, -1), 'variants': rng.sample(range(nv), pick(1, 1, min(2, nv)))}
        tw = pick(None, None, None, 'oob', 'empty', 'no_material', 'name', 'dup')
        if tw == 'oob': m['variants'].append(nv + pick(0, 3))
        if tw == 'empty': m['variants'] = []
        if tw == 'no_material': del m['material']
        if tw == 'name': m['name'] = pick('x', 1)
        if tw == 'dup': m['variants'] = m['variants'] * 2
        maps.append(m)
    b.prim()['extensions'] = {'KHR_materials_variants': {'mappings': maps}}
    if rng.random() < 0.3:
        second = copy.deepcopy(b.prim()); second['extensions']['KHR_materials_variants']['mappings'] = maps[:1]
        b.doc['meshes'][0]['primitives'].append(second)
    if rng.random() < 0.1: b.prim()['extensions']['KHR_materials_variants'] = pick({}, {'mappings': []})
    if rng.random() < 0.9: b.use('KHR_materials_variants', required=rng.random() < 0.1)
    return b.finish()


def shape_node_props():
    """Node properties: camera with mesh, weights without a mesh or with a mesh without targets,
    matrices that are singular, sheared, projective, mirrored or nearly orthonormal, TRS beside a
    matrix, rotations near unit length, zero or negative scale, a node root in one scene and child
    in another, loops through a second scene, a node in two scenes, nodes in no scene."""
    b = Builder(texture=False)
    b.doc['cameras'] = [{'type': 'perspective', 'perspective': {'yfov': 0.8, 'znear': 0.1}}]
    nodes = [{'mesh': 0}, {}, {}, {}]
    scenes = [{'nodes': [0, 1]}]
    for _ in range(pick(1, 1, 2)):
        i = rng.randrange(4)
        k = pick('camera', 'weights', 'matrix', 'trs_matrix', 'rotation', 'scale', 'translation')
        if k == 'camera': nodes[i]['camera'] = 0
        if k == 'weights': nodes[i]['weights'] = pick([0.5], [], [0, 0])
        if k == 'matrix':
            nodes[i]['matrix'] = pick([0] * 15 + [1], [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1], [1, 0, 0, 1, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1],
                                      [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, -1, 0, 3, 4, 5, 1], [1.0001, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1],
                                      [1, 0.0001, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1], [1, 0.01, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1],
                                      [0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1], [1e-9, 0, 0, 0, 0, 1e-9, 0, 0, 0, 0, 1e-9, 0, 0, 0, 0, 1],
                                      [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 2], IDENT)
        if k == 'trs_matrix': nodes[i]['matrix'] = IDENT; nodes[i][pick('translation', 'rotation', 'scale')] = pick([0, 0, 0], [0, 0, 0, 1], [1, 1, 1])
        if k == 'rotation':
            e = pick(0, 1e-7, 1e-6, 5e-6, 1e-5, 1e-4, 1e-3)
            nodes[i]['rotation'] = [0, 0, 0, pick(1 + e, 1 - e)] if rng.random() < 0.7 else [0, 0, 0.7071068, 0.7071068]
        if k == 'scale': nodes[i]['scale'] = pick([0, 0, 0], [0, 1, 1], [-1, -1, -1], [1e-30, 1, 1])
        if k == 'translation': nodes[i]['translation'] = pick([0, 0, 0], [1e38, 0, 0], [1, 2])
    g = pick('flat', 'flat', 'cross_scene_child', 'cross_loop', 'two_scenes', 'orphan', 'orphan_child')
    if g == 'cross_scene_child': nodes[1]['children'] = [2]; scenes.append({'nodes': [2, 3]})
    if g == 'cross_loop': nodes[2]['children'] = [3]; nodes[3]['children'] = [2]; scenes.append({'nodes': [2]})
    if g == 'two_scenes': scenes.append({'nodes': [0, pick(2, 1)]})
    if g == 'orphan_child': nodes[2]['children'] = [3]
    b.doc['nodes'] = nodes; b.doc['scenes'] = scenes
    b.doc['scene'] = pick(0, len(scenes) - 1)
    return b.finish()


KNOWN_EXTS = {'KHR_materials_unlit': ('material', {}), 'KHR_texture_transform': ('texinfo', {'offset': [0, 0]}),
              'KHR_materials_emissive_strength': ('material', {'emissiveStrength': 2}), 'KHR_mesh_quantization': (None, None),
              'KHR_lights_punctual': ('root', {'lights': [{'type': 'point'}]}), 'EXT_foo_bar': ('node', {}), 'ABC_thing': ('material', {}),
              'KHR_materials_ior': ('material', {'ior': 1.4}), 'KHR_texture_basisu': ('texture', {'source': 0})}


def shape_asset_extensions():
    """The asset object (version and minVersion strings, generator and copyright of odd types,
    extras, extensions) and extensionsUsed/extensionsRequired lists of several extensions, each
    actually present in the document or not, required or not, in any order, with non-string or
    repeated entries."""
    b = Builder()
    d = b.doc
    a = d['asset']
    if rng.random() < 0.5:
        a['version'] = pick('2.0', '2.0', '2.1', '2.10', '2.01', '3.0', '1.0', '0.9', '2', '2.0.0', 'x.y', '2.0a', '10.0', '2.-1')
        if rng.random() < 0.5: a['minVersion'] = pick('2.0', '2.1', '1.0', '1.9', '2.0.0', '3.0', '2.01', '2.00', '2', 'x')
    for k in rng.sample(['generator', 'copyright', 'extras', 'extensions', 'foo'], pick(0, 1, 2)):
        a[k] = {'generator': pick('gen', '', 1, None), 'copyright': pick('(c)', '', [1]), 'extras': pick({'a': 1}, 'x', [], None),
                'extensions': pick({}, {'EXT_foo_bar': {}}, {'KHR_materials_unlit': {}}), 'foo': pick(1, {})}[k]
    names = rng.sample(sorted(KNOWN_EXTS), pick(1, 2, 3))
    used, required = [], []
    for name in names:
        where, body = KNOWN_EXTS[name]
        present = rng.random() < 0.7
        if present and where == 'material': d['materials'][0].setdefault('extensions', {})[name] = dict(body)
        if present and where == 'texinfo': d['materials'][0]['pbrMetallicRoughness']['baseColorTexture']['extensions'] = {name: dict(body)}
        if present and where == 'root': d.setdefault('extensions', {})[name] = copy.deepcopy(body)
        if present and where == 'node': d['nodes'][0].setdefault('extensions', {})[name] = dict(body)
        if present and where == 'texture': d['textures'][0].setdefault('extensions', {})[name] = dict(body)
        if rng.random() < 0.85: used.append(name)
        if rng.random() < 0.35: required.append(name)
    if rng.random() < 0.1 and used: used.append(pick(used[0], 1, ''))
    if rng.random() < 0.1 and required: required.append(required[0])
    if rng.random() < 0.2: rng.shuffle(used)
    if used or rng.random() < 0.1: d['extensionsUsed'] = used
    if required or rng.random() < 0.1: d['extensionsRequired'] = required
    return b.finish(glb_chunk=rng.random() < 0.2)


SHAPES3 = {f.__name__[6:]: f for f in [shape_attributes, shape_indices, shape_skin_details, shape_anim_channels, shape_instancing,
                                        shape_variants, shape_node_props, shape_asset_extensions]}


def write_shape(n, work):
    table = {1: SHAPES, 2: SHAPES2, 3: SHAPES3, 4: dict(SHAPES, **SHAPES2, **SHAPES3)}[args.shapes_set]
    while True:
        name = rng.choice(sorted(table))
        try: doc, blob, container = table[name](); break
        except Exception: continue  # a shape's random choices that do not fit together: draw again
    if doc is not None and rng.random() < 0.15:
        try: mutate(doc, extensions)
        except Exception: pass
    base = os.path.join(work, 'gen', '%s_%05d' % (name, n))
    if isinstance(container, tuple):  # a document with companion files beside it
        container, files = container
        for suffix, data in files.items(): open(base + suffix, 'wb').write(data)
        open(base + '.gltf', 'w').write(dumps(doc).replace('%BASE%', os.path.basename(base))); return base + '.gltf'
    if container == 'raw':
        open(base + '.gltf', 'wb').write(blob); return base + '.gltf'
    if container == 'glb':
        open(base + '.glb', 'wb').write(glb(dumps(doc), blob, None)); return base + '.glb'
    open(base + '.gltf', 'w').write(dumps(doc)); return base + '.gltf'


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
    if args.new_share > 0 and rng.random() < args.new_share:
        written.append(write_shape(n, args.work))
        continue
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
