# Compares ref.jsonl (reference_reports.mjs) with ours.jsonl (structure_bench --json), one report
# per line in the same order. Prints the share of inputs whose ordered (code, pointer or offset,
# severity) lists are equal, by source (the folder under the work folder: gen, assets, suite), the
# order-only differences, the inputs the reference refused outright, and the issue keys that only
# one side has, most frequent first.
#   python3 compare_reports.py [--examples=N] ["ours-only CODE sev0" ...]  (examples of named keys)
import difflib, json, sys
from collections import Counter, defaultdict

names = [a for a in sys.argv[1:] if not a.startswith('--')]
ref = [json.loads(line) for line in open('ref.jsonl')]
ours = [json.loads(line) for line in open('ours.jsonl')]
assert len(ref) == len(ours), 'ref.jsonl and ours.jsonl differ in length'


def key(message):
    return (message['code'], str(message.get('pointer', message.get('offset'))), message['severity'])


# What the catalogue (2.0.0-dev.3.11, the suite's version) changed against the npm build
# (2.0.0-dev.3.10): a skinned mesh's node that is not a root is information in 3.11 (a warning in
# 3.10), and parent transforms of such a node are a separate 3.11 warning. Our issues are put in
# their 3.10 form before comparing; the raw agreement is printed too.
# Extensions the catalogue (3.11) knows and the npm build (3.10) does not: an input that uses one
# is counted in its own class, not in the agreement.
NEWER_EXTENSIONS = ('KHR_node_visibility',)


def uses_newer_extension(report):
    return any(m['code'] == 'UNSUPPORTED_EXTENSION' and any(e in m['message'] for e in NEWER_EXTENSIONS)
               for m in report['issues']['messages'])


# Array properties whose next pointer token must be an index. The npm build sometimes names an
# issue with a pointer left over from an earlier object ("/animations/0/channels/samplers/3",
# "/animations/cameras/1"); such reports are counted in their own class.
ARRAYS = {'accessors', 'animations', 'buffers', 'bufferViews', 'cameras', 'images', 'materials', 'meshes', 'nodes',
          'samplers', 'scenes', 'skins', 'textures', 'channels', 'primitives'}


def malformed_pointer(report):
    for m in report['issues']['messages']:
        tokens = m.get('pointer', '').split('/')[1:]
        if any(t in ARRAYS and not u.isdigit() for t, u in zip(tokens, tokens[1:])): return True
    return False


def as_reference_version(keys):
    out = []
    for code, pointer, severity in keys:
        if code == 'NODE_SKINNED_MESH_PARENT_TRANSFORMS': continue
        if code == 'NODE_SKINNED_MESH_NON_ROOT': severity = 1
        out.append((code, pointer, severity))
    return out


def source(uri):
    for part in ('/gen/', '/assets/', '/suite/'):
        if part in uri: return part.strip('/')
    return 'other'


totals, agreed = Counter(), Counter()
classes, examples = Counter(), defaultdict(list)
order_only = refused = raw_agreed = newer = malformed = 0
for r, o in zip(ref, ours):
    where = source(r['uri'])
    totals[where] += 1
    if 'exception' in r:
        refused += 1
        classes['reference refused: ' + r['exception'][:60]] += 1
        continue
    if malformed_pointer(r):
        malformed += 1
        classes['the reference names a malformed pointer'] += 1
        continue
    if uses_newer_extension(r):
        newer += 1
        classes['uses an extension newer than the npm build'] += 1
        continue
    a = [key(m) for m in r['issues']['messages']]
    # Ours folds identical repeats into one message with a count; the reference lists each.
    b = [key(m) for m in o['issues']['messages'] for _ in range(m.get('count', 1))]
    raw_agreed += a == b
    b = as_reference_version(b)
    if a == b:
        agreed[where] += 1
        continue
    if sorted(a) == sorted(b):
        order_only += 1
        classes['ORDER'] += 1
        examples['ORDER'].append((r['uri'], a, b))
        continue
    ca, cb = Counter(a), Counter(b)
    for k in sorted({(k[0], k[2]) for k in ca - cb}):
        name = 'ref-only %s sev%d' % k
        classes[name] += 1
        examples[name].append((r['uri'], a, b))
    for k in sorted({(k[0], k[2]) for k in cb - ca}):
        name = 'ours-only %s sev%d' % k
        classes[name] += 1
        examples[name].append((r['uri'], a, b))

total = sum(totals.values()) - refused - newer - malformed  # inputs both sides judged, in one catalogue version
print('agree %d of %d (%.1f%%; %d, %.1f%% before the 3.11 changes are undone), order-only %d; '
      'not compared: %d refused by the reference, %d using a 3.11 extension, %d with a malformed reference pointer' %
      (sum(agreed.values()), total, 100.0 * sum(agreed.values()) / total, raw_agreed, 100.0 * raw_agreed / total,
       order_only, refused, newer, malformed))
for where in sorted(totals):
    print('  %-7s %5d of %5d inputs' % (where, agreed[where], totals[where]))
for name, count in classes.most_common():
    print('%5d %s' % (count, name))
def runs(keys):
    """The keys as text, a run of equal keys as one line with its length."""
    out = []
    for k in keys:
        if out and out[-1][0] == k: out[-1][1] += 1
        else: out.append([k, 1])
    return [str(k) + (' x%d' % n if n > 1 else '') for k, n in out]


examples_each = next((int(a.split('=')[1]) for a in sys.argv[1:] if a.startswith('--examples=')), 3)
for name in names:
    for uri, a, b in examples.get(name, [])[:examples_each]:
        print('\n## %s %s' % (name, uri))
        for line in difflib.unified_diff(runs(a), runs(as_reference_version(b)), 'ref', 'ours', n=1, lineterm=''):
            print('   ' + line)
