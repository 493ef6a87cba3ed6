#!/usr/bin/python3
"""Metalness levels on inputs they were not tuned on: every distinct PNG and JPEG image in
../shared/assets (but BoxTextured's, whose asset the default was looked at on) as the diffuse
texture of a spec-gloss material on BoxTextured's box, under a grey specular of 0.1, 0.3 and 0.6
and glossiness 0.5. Converts each with --metalness-tolerance 0 and with the default, and prints
the maps that moved, their bytes and the rise of the judged error (diffuse + F0 means, reading A).
  bench/levels/heldout.py GLTF_PBR [SHARED_DIR]"""
import glob, json, os, shutil, subprocess, sys, tempfile

tool = sys.argv[1]
shared = sys.argv[2] if len(sys.argv) > 2 else os.path.join(os.path.dirname(__file__), '../../../shared')
box = os.path.join(shared, 'assets/BoxTextured/specgloss')
document = json.load(open(os.path.join(box, 'BoxTextured.gltf')))
work = tempfile.mkdtemp(prefix='gltf-pbr-levels-')
images = sorted(set(glob.glob(f'{shared}/assets/*/*/*.png') + glob.glob(f'{shared}/assets/*/*/*.jpg')))
seen, rows = set(), []
for image in images:
    if 'BoxTextured' in image or (os.path.basename(image), os.path.getsize(image)) in seen:
        continue
    seen.add((os.path.basename(image), os.path.getsize(image)))
    for specular in (0.1, 0.3, 0.6):
        case = os.path.join(work, f'case{len(rows):03d}')
        os.makedirs(case)
        shutil.copy(os.path.join(box, 'BoxTextured0.bin'), case)
        extension = os.path.splitext(image)[1]
        shutil.copy(image, os.path.join(case, 'diffuse' + extension))
        g = json.loads(json.dumps(document))
        g['images'] = [{'uri': 'diffuse' + extension}]
        g['materials'] = [{'pbrMetallicRoughness': {'baseColorTexture': {'index': 0}},
                           'extensions': {'KHR_materials_pbrSpecularGlossiness': {
                               'diffuseTexture': {'index': 0}, 'specularFactor': [specular] * 3,
                               'glossinessFactor': 0.5}}}]
        json.dump(g, open(os.path.join(case, 'm.gltf'), 'w'))
        result = {}
        for tolerance in ('0', None):
            out = os.path.join(case, 'every' if tolerance else 'default')
            options = ['--metalness-tolerance', tolerance] if tolerance else []
            subprocess.run([tool, 'convert', '-q', os.path.join(case, 'm.gltf'), '-o', out + '/m.gltf',
                            '--report', out + '.json', *options], check=True)
            m = json.load(open(out + '.json'))['files'][0]['materials'][0]
            a = m['deltaE2000']['readingA']
            result[tolerance] = (a['diffuse']['mean'] + a['f0']['mean'], m.get('metalnessLevels'),
                                 sum(os.path.getsize(f) for f in glob.glob(out + '/*metallicRoughness*')))
        rows.append((os.path.relpath(image, shared + '/assets'), specular, result['0'], result[None]))
moved = [r for r in rows if r[3][1] and r[3][1]['written'] < r[3][1]['solved']]
before, after = sum(r[2][2] for r in rows), sum(r[3][2] for r in rows)
rises = [r[3][0] - r[2][0] for r in rows]
print(f'{len(rows)} materials, {sum(1 for r in rows if r[2][2])} with a metalness map, {len(moved)} moved; '
      f'map bytes {before:,} -> {after:,} ({after / before:.2f}); judged error rise: max {max(rises):+.4f}, '
      f'min {min(rises):+.4f}, lower in {sum(1 for x in rises if x < -1e-9)}')
print('| diffuse image | specular | values | map bytes | judged error |')
print('|---|---|---|---|---|')
for image, specular, every, default in moved:
    print(f"| {image} | {specular} | {default[1]['solved']} → {default[1]['written']} | {every[2]:,} → {default[2]:,} "
          f"| {every[0]:.3f} → {default[0]:.3f} ({default[0] - every[0]:+.4f}) |")
shutil.rmtree(work)
