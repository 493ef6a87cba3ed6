# Compares ref.jsonl (reference_reports.mjs) with ours.jsonl (structure_bench --json), one report
# per line in the same order: shares of equal ordered (code, pointer, severity) lists, order-only
# differences, and the issue keys only one side has, most frequent first.
#   python3 compare_reports.py ["ours-only CODE sev0" ...]   (prints one example per named key)
import json, sys
from collections import Counter
ref=[json.loads(l) for l in open('ref.jsonl')]
ours=[json.loads(l) for l in open('ours.jsonl')]
agree=0; unordered=0
cat=Counter(); examples={}
for r,o in zip(ref,ours):
    key=lambda m:(m['code'],str(m.get('pointer',m.get('offset'))),m['severity'])
    a=[key(m) for m in r['issues']['messages']]; b=[key(m) for m in o['issues']['messages']]
    if a==b: agree+=1; continue
    if sorted(a)==sorted(b): unordered+=1; cat['ORDER']+=1; examples.setdefault('ORDER',(r['uri'],a,b)); continue
    ca,cb=Counter(a),Counter(b)
    for k in (ca-cb): cat['ref-only '+k[0]+' sev'+str(k[2])]+=1; examples.setdefault('ref-only '+k[0]+' sev'+str(k[2]),(r['uri'],a,b))
    for k in (cb-ca): cat['ours-only '+k[0]+' sev'+str(k[2])]+=1; examples.setdefault('ours-only '+k[0]+' sev'+str(k[2]),(r['uri'],a,b))
print('agree',agree,'order-only',unordered,'of',len(ref))
for k,v in cat.most_common(): print(v,k)
if len(sys.argv)>1:
    for k in sys.argv[1:]:
        e=examples.get(k)
        if e: print('\n##',k,e[0]); print(' ref :',e[1]); print(' ours:',e[2])
