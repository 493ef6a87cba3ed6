#!/usr/bin/python3
"""The error models judged by the preview on materials neither model was chosen on (issue 12): new
pairings of the shared images and meshes (the grey speculars may overlap the constructed spheres'
0, 0.02, 0.1 and 0.2). Every distinct PNG and JPEG image in ../shared/assets as the diffuse texture
of a spec-gloss material on one shared asset's mesh, under grey speculars and glossinesses given on
the command line. Each is drawn by `gltf-pbr preview` under both error models, lit by the built-in
sky and sun, by `--env neutral` (a uniform white environment without a sun, in which every
direction mirrors the same grey) or by `--env FILE` (an equirectangular .hdr or .exr); prints the
ΔE2000 and FLIP means over the cases, how many cases each model draws closer (and how many alike),
and the mean per setting. The mesh must be textured (TEXCOORD_0 on every primitive).
  bench/preview/appearance_heldout.py GLTF_PBR [SHARED_DIR] [--mesh Avocado] [--specular 0,0.1,0.3]
                                      [--glossiness 0.3,1.0] [--size 128] [--env neutral|FILE]"""
import argparse, glob, json, os, shutil, statistics, subprocess, sys, tempfile

parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
parser.add_argument('tool')
parser.add_argument('shared', nargs='?', default=os.path.join(os.path.dirname(__file__), '../../../shared'))
parser.add_argument('--mesh', default='Avocado')
parser.add_argument('--specular', default='0,0.1,0.3')
parser.add_argument('--glossiness', default='0.3,1.0')
parser.add_argument('--size', default='128')
parser.add_argument('--env', help="'neutral' or an .hdr/.exr file; default: the built-in sky and sun")
args = parser.parse_args()
mesh_dir = os.path.join(args.shared, 'assets', args.mesh, 'specgloss')
with open(os.path.join(mesh_dir, args.mesh + '.gltf')) as f:
    document = json.load(f)
# Every primitive takes the one material, whose diffuse texture reads TEXCOORD_0.
for mesh in document['meshes']:
    for primitive in mesh['primitives']:
        if 'TEXCOORD_0' not in primitive['attributes']:
            sys.exit(f'{args.mesh}: a primitive has no TEXCOORD_0 for the diffuse texture; take a textured mesh')
        primitive['material'] = 0
speculars = [float(x) for x in args.specular.split(',')]
glossinesses = [float(x) for x in args.glossiness.split(',')]
models = ('normal-incidence', 'appearance')

work = tempfile.TemporaryDirectory(prefix='gltf-pbr-appearance-')
lighting, lit_by = [], args.env or 'the built-in sky and sun'
if args.env == 'neutral':
    # A flat Radiance picture (Ward 1991), the same everywhere: RGBE (128, 128, 128, 129), which
    # decodes as (m + 0.5) 2^(e - 136) = 1.0039 (no RGBE value is exactly 1). Four pixels wide,
    # below the width of 8 at which scanlines may be run-length encoded.
    neutral = os.path.join(work.name, 'neutral.hdr')
    with open(neutral, 'wb') as f:
        f.write(b'#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X 4\n' + bytes([128, 128, 128, 129]) * 8)
    lighting, lit_by = ['--env', neutral, '--no-sun'], 'a uniform white environment'
elif args.env:
    lighting = ['--env', os.path.abspath(args.env)]
images = sorted(set(glob.glob(f'{args.shared}/assets/*/*/*.png') + glob.glob(f'{args.shared}/assets/*/*/*.jpg')))
seen, cases = set(), []
for image in images:
    if (os.path.basename(image), os.path.getsize(image)) in seen:
        continue
    seen.add((os.path.basename(image), os.path.getsize(image)))
    for specular in speculars:
        for glossiness in glossinesses:
            case = os.path.join(work.name, f'case{len(cases):03d}')
            os.makedirs(case)
            for buffer in glob.glob(os.path.join(mesh_dir, '*.bin')):
                shutil.copy(buffer, case)
            extension = os.path.splitext(image)[1]
            shutil.copy(image, os.path.join(case, 'diffuse' + extension))
            g = json.loads(json.dumps(document))
            g['images'] = [{'uri': 'diffuse' + extension}]
            g['textures'] = [{'source': 0}]
            g.pop('samplers', None)
            g['materials'] = [{'extensions': {'KHR_materials_pbrSpecularGlossiness': {
                'diffuseTexture': {'index': 0}, 'specularFactor': [specular] * 3, 'glossinessFactor': glossiness}}}]
            used = [e for e in g.get('extensionsUsed', []) if e != 'KHR_materials_pbrSpecularGlossiness']
            g['extensionsUsed'] = used + ['KHR_materials_pbrSpecularGlossiness']
            with open(os.path.join(case, 'm.gltf'), 'w') as f:
                json.dump(g, f)
            figures = {}
            for model in models:
                out = os.path.join(case, model)
                subprocess.run([args.tool, 'preview', '-q', '--no-gallery', '--size', args.size, '--error-model', model,
                                *lighting, os.path.join(case, 'm.gltf'), '-o', out], check=True)
                with open(os.path.join(out, 'report.json')) as f:
                    difference = json.load(f)['difference']
                figures[model] = (difference['delta_e_2000']['mean'], difference['flip']['mean'])
            cases.append(((specular, glossiness), figures))
work.cleanup()

settings = [(s, g) for s in speculars for g in glossinesses]
print(f'{len(cases)} materials ({len(seen)} images on {args.mesh}\'s mesh, {args.size}² previews, '
      f'{lit_by})')
ties = sum(1 for _, f in cases if f[models[0]][0] == f[models[1]][0])
print(f'{ties} drawn alike by both (the same conversion)')
print('| error model | ΔE2000 mean | FLIP mean | drawn closer (ΔE2000 mean) in | ΔE2000 mean by (specular, glossiness) |')
print('|---|---|---|---|---|')
for model in models:
    other = models[1 - models.index(model)]
    closer = sum(1 for _, f in cases if f[model][0] < f[other][0])
    by = ', '.join(f'({s:g}, {g:g}) {statistics.mean(f[model][0] for k, f in cases if k == (s, g)):.2f}'
                   for s, g in settings)
    print(f'| {model} | {statistics.mean(f[model][0] for _, f in cases):.3f} | '
          f'{statistics.mean(f[model][1] for _, f in cases):.4f} | {closer} of {len(cases)} | {by} |')
