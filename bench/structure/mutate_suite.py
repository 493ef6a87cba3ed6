# Differential test inputs: JSON-level mutations (deleted properties, shifted indices, changed
# enums, duplicated array elements, non-object extras) of every .gltf of a COPY of the Khronos
# suite's test folder, written beside the originals as *.mutN.gltf; the list goes to list.txt.
# Run it in the copy's root (never in ../shared).   python3 mutate_suite.py
import json, glob, random, copy, os
random.seed(7)
out = []
def walk(node, path=()):
    if isinstance(node, dict):
        for k, v in node.items():
            yield path + (k,), v
            yield from walk(v, path + (k,))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield path + (i,), v
            yield from walk(v, path + (i,))
def set_at(doc, path, value):
    cur = doc
    for p in path[:-1]: cur = cur[p]
    cur[path[-1]] = value
def del_at(doc, path):
    cur = doc
    for p in path[:-1]: cur = cur[p]
    del cur[path[-1]]
for f in sorted(glob.glob('test/**/*.gltf', recursive=True)):
    if '.mut' in f: continue
    try: doc = json.load(open(f))
    except Exception: continue
    if not isinstance(doc, dict): continue
    paths = [p for p, v in walk(doc)]
    for m in range(6):
        d = copy.deepcopy(doc)
        if not paths: break
        p = random.choice(paths)
        try:
            cur = d
            for q in p: cur = cur[q]
            kind = random.randrange(6)
            if kind == 0: del_at(d, p)
            elif kind == 1 and isinstance(cur, int) and not isinstance(cur, bool): set_at(d, p, cur + random.choice([1, 5, -1, 100]))
            elif kind == 2 and isinstance(cur, (int, float)) and not isinstance(cur, bool): set_at(d, p, random.choice([0, -1, 0.5, 1.5, 3, 4, 5126, 5121, 34963]))
            elif kind == 3 and isinstance(cur, str): set_at(d, p, random.choice(['', 'VEC2', 'MASK', 'BLEND', 'rotation', 'weights', 'CUBICSPLINE', 'STEP', 'image/jpeg']))
            elif kind == 4 and isinstance(cur, list) and cur: cur.append(copy.deepcopy(cur[0]))
            elif kind == 5 and isinstance(cur, dict): cur['extras'] = 1
            else: del_at(d, p)
        except Exception:
            continue
        name = f[:-5] + '.mut%d.gltf' % m
        json.dump(d, open(name, 'w'))
        out.append(name)
print(len(out))
open('list.txt', 'w').write('\n'.join(out))
