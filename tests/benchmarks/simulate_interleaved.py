#!/usr/bin/env python3
"""What-if (not the runner as built): the search steps of all design x grid batches
interleaved (global step j = step j of every batch), chunks round-robin, LPT on the actual costs,
LPT on the previous step's costs, and on-demand hand-out; units in one pool; serial work spread.
Usage: simulate_interleaved.py [record.csv.gz]"""
import sys, math, gzip, csv
sys.path.insert(0, __import__('os').path.dirname(__file__))
import simulate_distribution as sd
path=sys.argv[1] if len(sys.argv) > 1 else 'tests/benchmarks/data/compare_designs_unit_costs_shared.csv.gz'
rows=[]
with gzip.open(path,'rt') as f:
    for r in csv.DictReader(f):
        rows.append((r['unit'], float(r['cpu_seconds'])))
# searches: list of list of steps (each step = list of chunk costs), per batch
searches=[]; units=[]; cur=None; laststep=None
for u,c in rows:
    if u.startswith('share:search/'):
        if cur is None: cur=[]; searches.append(cur); laststep=None
        if u!=laststep: cur.append([]); laststep=u
        cur[-1].append(c)
    elif u.startswith('share:audit'):
        cur=None
        searches.append([[c]])
    else:
        cur=None; units.append(c)
R=5
searches=searches*R; units=units*R
T1=sum(units)+sum(sum(sum(s) for s in st) for st in searches)+4*R
print('T1',T1,'searches',len(searches),'max steps',max(len(s) for s in searches))
lat=5e-6
for N in [2,16,64,256,1024]:
    for per_rr in ['chunk64']:
        nsteps=max(len(s) for s in searches)
        tot=0
        for j in range(nsteps):
            chunks=[c for s in searches if j<len(s) for c in s[j]]
            load=[0.0]*N
            for k,c in enumerate(chunks): load[k%N]+=c
            # LPT balance what-if
            tot+=max(load)+2*math.log2(N)*lat
        lpt=0
        import heapq
        for j in range(nsteps):
            chunks=sorted([c for s in searches if j<len(s) for c in s[j]],reverse=True)
            h=[0.0]*N
            for c in chunks:
                x=heapq.heappop(h); heapq.heappush(h,x+c)
            lpt+=max(h)+2*math.log2(N)*lat
        t,_,_=sd.simulate_batch([(c,14000) for c in units],N,lat,5e-6,5e-4,5e9,False)
        ser=4*R/N*1.0
        for name,st in [('rr',tot),('lpt',lpt)]:
            mk=t+ser+st
            print(N,name,'steps %.2f units %.2f total %.2f eff %.0f%%'%(st,t,mk,100*T1/(N*mk)))
print('--- LPT on the previous step costs (predicted), and dynamic list scheduling')
for N in [2,16,64,256,1024]:
    nsteps=max(len(s) for s in searches)
    prev={}
    tot=0; dyn=0
    for j in range(nsteps):
        items=[((b,k),c) for b,s in enumerate(searches) if j<len(s) for k,c in enumerate(s[j])]
        pred=[(prev.get(key, 1e-4),key,c) for key,c in items]
        pred.sort(key=lambda x:(-x[0],x[1]))
        h=[(0.0,0.0,r) for r in range(N)]  # (predicted load, actual load, rank)
        heapq.heapify(h)
        act=[0.0]*N
        for p,key,c in pred:
            pl,al,r=heapq.heappop(h); act[r]+=c; heapq.heappush(h,(pl+p,al+c,r))
        tot+=max(act)+2*math.log2(N)*lat+ 1e-6*len(items)/N
        for key,c in items: prev[key]=c
        # dynamic: chunks in order to the first free rank, each hand-out costs 2 lat + 5us service serial at master
        free=[(0.0,r) for r in range(N)]; heapq.heapify(free); master=0.0; end=0.0
        for key,c in items:
            t,r=heapq.heappop(free); start=max(t+lat,master); master=start+5e-6; done=master+lat+c
            end=max(end,done); heapq.heappush(free,(done,r))
        dyn+=end+2*math.log2(N)*lat
    t,_,_=sd.simulate_batch([(c,14000) for c in units],N,lat,5e-6,5e-4,5e9,False)
    ser=4*R/N
    for name,st in [('predicted-lpt',tot),('dynamic',dyn)]:
        mk=t+ser+st
        print(N,name,'steps %.2f total %.2f eff %.0f%%'%(st,mk,100*T1/(N*mk)))
