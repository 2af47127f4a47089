#!/usr/bin/env python3
"""Simulates the distributed unit runner (src/study/distributed.cpp) on many ranks.

Input: a per-unit cost record of a real run (ARMSTUDY_UNIT_TIMES=units.csv armstudy run ...
--threads 1; columns unit,seconds,cpu_seconds,threads,rank,bytes,part). Units are grouped into batches
by id (everything before the last '/'), in file order, as the stages run them. Lines whose unit is
"share:<id>" are the chunks of a shared loop as the runner cut them (UnitRunner::share,
SharedLoop::chunks: a reach map search step's 1 to 8 poses of its active set, an audit's or a
multistart step's single poses, a grid's files one design or compared pair), consecutive lines of one
id forming one step.

Model, per batch (batches run one after another, as every rank runs the stages in lockstep):
  * rank 0 computes and, on a second thread, hands out chunks of the batch's units on demand:
    guided chunks of max(1, remaining / (4 N)) units (--single: one unit per hand-out);
  * a worker's request travels `latency` seconds, waits for rank 0's hand-out thread (one request
    at a time, `service` seconds each, plus up to `poll` seconds when the thread was idle and
    sleeping between probes), and the reply travels `latency` seconds back;
  * a unit costs its recorded CPU seconds (times --scale) on the rank that computes it;
  * when every rank is done, the batch's result bytes go to every rank: sizes (an allgather,
    log2(N) latencies) and one broadcast per rank that computed something (log2(N) latencies
    each, the bytes at `bandwidth` bytes/s into every rank, which loads the others' units at `apply`
    seconds per byte);
  * then every rank merges the batch and runs the stage's serial work (files, merges):
    `serial` seconds per batch, the same on every rank (it does not shrink with N);
  * a shared step (the search's Jacobi rounds, the audit, the files) has its recorded chunks owned
    round-robin (as src/study/distributed.cpp does, each rank computing its chunks in one call); it
    takes the busiest rank's chunks plus one allgather of the adopted rows (2 log2(N) latencies,
    the bytes at `bandwidth`, and every rank applies the others' bytes at `apply` seconds per byte);
    --unshared: every rank computes every step (as before the
    shared loops), i.e. the step costs its whole work on every rank.
Makespan = sum over batches; efficiency = T1 / (N x makespan) with T1 = the single process
(sum of unit costs + shared steps + serial work); master load = busy time of rank 0's hand-out thread / makespan.

--replicate R stands for R times the variants: every batch R times; with --interleaved (a record of
a run whose searches advance interleaved, "share:interleaved/..." steps: src/study/interleave.hpp)
the R copies of a grid's designs join the same combined steps (a step's chunks R times), as the
runner does with all the designs of a grid; without it the copies' steps follow one another.

--groups R (a record with the part column): the grids' map searches also replayed in rank groups of
at least R ranks as src/study/stage.cpp's planRankGroups forms them (weights: armstudy's prediction
from the recorded run's summary.json and designs.json, --run-dir; or the recorded costs, or equal),
each group's steps among its ranks, then every search's changed rows to every rank; the makespan
table then includes them.

Usage:
  simulate_distribution.py units.csv [--replicate R] [--serial-total S] [--ranks 16,64,256,1024]
      [--latency 5e-6] [--service 5e-6] [--poll 5e-4] [--bandwidth 5e9] [--apply 1.1e-9] [--single] [--group G]
      [--one-pool] [--unshared] [--interleaved] [--pool-per-grid] [--bounds] [--ceiling]
      [--groups R --serial-search S --group-weights model|oracle|equal --run-dir DIR]
"""
import argparse
import csv
import gzip
import heapq
import math
from collections import OrderedDict


def load_phases(path, scale, group):
    """The record in file order as phases: ("units", [(cost, bytes)]) for a batch of units (`group`
    consecutive recorded units form one unit) and ("step", [(cost, bytes)]) for a shared step's
    chunks (("files", ...) for a grid's files loop)."""
    phases = []
    with (gzip.open(path, "rt") if path.endswith(".gz") else open(path)) as f:
        for row in csv.DictReader(f):
            unit = row["unit"]
            cost = float(row.get("cpu_seconds") or row["seconds"]) * scale
            item = (cost, int(row.get("bytes") or 0))
            if unit.startswith("share:"):
                # A grid's files loop: each rank writes the files it rendered; the names travel.
                kind, key = ("files" if unit.startswith("share:files/") else "step"), unit
            else:
                kind, key = "units", unit.rsplit("/", 1)[0] if "/" in unit else unit.split("-")[0]
            if phases and phases[-1][0] == kind and phases[-1][1] == key:
                phases[-1][2].append(item)
            else:
                phases.append((kind, key, [item]))
    out = []
    for kind, _, items in phases:
        if kind == "units":
            items = [(sum(c for c, _ in items[i:i + group]), sum(b for _, b in items[i:i + group]))
                     for i in range(0, len(items), group)]
        out.append((kind, items))
    return out


def pool_per_grid(phases):
    """The unit batches that follow one another (the designs of one grid) as one batch: the runner
    since 2026-11-26 hands out every design's units of a grid from one pool (runUnitBatches)."""
    out = []
    for kind, items in phases:
        if kind == "units" and out and out[-1][0] == "units":
            out[-1] = ("units", out[-1][1] + items)
        else:
            out.append((kind, items))
    return out


def replicate(phases, r, interleaved):
    """R times the variants. Not interleaved: the whole record R times. Interleaved: per segment
    (a run of unit batches, then the shared steps that follow them, i.e. one grid), the batches R
    times and each step with its chunks R times (the copies' designs in the same combined step)."""
    if not interleaved:
        return phases * r
    out, i = [], 0
    while i < len(phases):
        j = i
        while j < len(phases) and phases[j][0] == "units":
            j += 1
        k = j
        while k < len(phases) and phases[k][0] != "units":
            k += 1
        out += phases[i:j] * r
        out += [(kind, items * r) for kind, items in phases[j:k]]
        i = k
    return out


def simulate_step(chunks, n, latency, bandwidth, unshared, apply=0.0):
    """Seconds of one shared step on n ranks (chunks: the recorded chunks)."""
    work = sum(c for c, _ in chunks)
    if n == 1:
        return work
    if unshared:
        return work
    load = [0.0] * n
    for k, (c, _) in enumerate(chunks):  # the recorded chunks are the run's chunks
        load[k % n] += c
    total_bytes = sum(b for _, b in chunks)
    return max(load) + 2 * math.log2(n) * latency + total_bytes / bandwidth + total_bytes * (n - 1) / n * apply


def simulate_batch(units, n, latency, service, poll, bandwidth, single, apply=0.0):
    """Makespan of one batch's unit phase and exchange on n ranks; returns (seconds, master busy, hand-outs)."""
    costs = [c for c, _ in units]
    total_bytes = sum(b for _, b in units)
    nxt = 0
    remaining = len(costs)

    def take():
        nonlocal nxt, remaining
        k = 1 if single else max(1, remaining // (4 * n))
        k = min(k, remaining)
        chunk = costs[nxt:nxt + k]
        nxt += k
        remaining -= k
        return chunk

    master_free = 0.0  # when rank 0's hand-out thread is next free
    master_busy = 0.0
    handouts = 0
    computed_by = set()
    # Events: (time the rank is free, rank).
    events = [(0.0, r) for r in range(n)]
    heapq.heapify(events)
    finish = 0.0
    while events:
        t, r = heapq.heappop(events)
        if r == 0:  # rank 0 takes from the pool directly
            chunk = take()
            if not chunk:
                finish = max(finish, t)
                continue
            computed_by.add(r)
            heapq.heappush(events, (t + sum(chunk), r))
            continue
        arrive = t + latency
        start = max(arrive, master_free)
        if arrive > master_free:
            start += poll / 2  # the idle hand-out thread sleeps between probes (mean delay)
        master_free = start + service
        master_busy += service
        handouts += 1
        chunk = take()
        reply = master_free + latency
        if not chunk:
            finish = max(finish, reply)
            continue
        computed_by.add(r)
        heapq.heappush(events, (reply + sum(chunk), r))
    log_n = math.log2(n) if n > 1 else 0
    exchange = log_n * latency * (1 + len(computed_by)) + (total_bytes / bandwidth if n > 1 else 0) + \
        total_bytes * (n - 1) / n * apply
    return finish + exchange, master_busy, handouts


def load_search_parts(path, scale):
    """Per grid (in record order): the map searches' steps by program ("part" column of the combined
    chunks: src/study/interleave.cpp) and the bytes of each program's initial sweep units (the size of
    its final map, which a grouped run sends to every rank once its search has ended). Returns a list
    of (programs, step lists, unit bytes): steps[p] = [[(cost, bytes)] per step of program p]."""
    grids = OrderedDict()
    with (gzip.open(path, "rt") if path.endswith(".gz") else open(path)) as f:
        last_key = None
        for row in csv.DictReader(f):
            unit = row["unit"]
            cost = float(row.get("cpu_seconds") or row["seconds"]) * scale
            b = int(row.get("bytes") or 0)
            if not unit.startswith("share:"):
                parts = unit.split("/")  # stage/grid/design/units_...
                g = grids.setdefault(parts[1], {"steps": OrderedDict(), "unit_bytes": OrderedDict(), "designs": []})
                if parts[2] not in g["unit_bytes"]:
                    g["designs"].append(parts[2])
                g["unit_bytes"][parts[2]] = g["unit_bytes"].get(parts[2], 0) + b
                last_key = None
                continue
            if "/search/" not in unit or not row.get("part"):
                last_key = None
                continue
            grid = list(grids)[-1]
            g = grids[grid]
            p = int(row["part"])
            if unit != last_key:  # a new combined step: every program in it starts its next step
                g["steps"].setdefault("_current", set()).clear()
                last_key = unit
            cur = g["steps"].setdefault("_current", set())
            prog = g["steps"].setdefault(p, [])
            if p not in cur:
                prog.append([])
                cur.add(p)
            prog[-1].append((cost, b))
    out = []
    for g in grids.values():
        steps = {p: v for p, v in g["steps"].items() if p != "_current"}
        if not steps:
            continue
        ub = [g["unit_bytes"][d] for d in g["designs"]]
        out.append((sorted(steps), steps, ub))
    return out


def load_chains(path, scale):
    """The longest chain of pieces that must run one after another, per grid and design: the
    design's costliest unit (its sweep must be whole before its search starts), then in each of its
    map search's and audit's steps the costliest chunk (a step waits for the one before), and, on its
    own, a grid's costliest files piece. Returns (seconds of the longest chain, its name)."""
    best = (0.0, "")
    grid = None
    unit_max = OrderedDict()   # (grid, design) -> costliest unit
    steps = OrderedDict()      # (grid, kind, part) -> [max chunk per step]
    last_key = None
    seen = set()
    with (gzip.open(path, "rt") if path.endswith(".gz") else open(path)) as f:
        for row in csv.DictReader(f):
            unit = row["unit"]
            cost = float(row.get("cpu_seconds") or row["seconds"]) * scale
            if not unit.startswith("share:"):
                parts = unit.split("/")
                grid = parts[1]
                key = (grid, parts[2])
                unit_max[key] = max(unit_max.get(key, 0.0), cost)
                last_key = None
                continue
            if unit.startswith("share:files/"):
                best = max(best, (cost, "a files piece of " + unit[len("share:files/"):]))
                last_key = None
                continue
            kind = "search" if "/search/" in unit else "audit" if "/audit/" in unit else None
            if kind is None or not row.get("part"):
                last_key = None
                continue
            if unit != last_key:
                seen = set()
                last_key = unit
            k = (grid, kind, int(row["part"]))
            lst = steps.setdefault(k, [])
            if k not in seen:
                lst.append(0.0)
                seen.add(k)
            lst[-1] = max(lst[-1], cost)
    designs = OrderedDict()
    for (g, d) in unit_max:
        designs.setdefault(g, []).append(d)
    for (g, d), u in unit_max.items():
        p = designs[g].index(d)
        chain = u + sum(steps.get((g, "search", p), [])) + sum(steps.get((g, "audit", p), []))
        best = max(best, (chain, f"{g}/{d}: costliest unit, {len(steps.get((g, 'search', p), []))} search "
                                 f"steps, {len(steps.get((g, 'audit', p), []))} audit steps"))
    return best


def replicate_grids(grids, model, r):
    """R copies of every grid's searches (--replicate with --groups): the copies' designs join the
    grid's programs, as the runner would interleave R times the variants."""
    if r == 1:
        return grids, model
    out, out_model = [], []
    for gi, (progs, steps, ub) in enumerate(grids):
        top = max(progs) + 1
        nprogs, nsteps, nub, w = [], {}, [], []
        for k in range(r):
            for i, p in enumerate(progs):
                nprogs.append(p + k * top)
                nsteps[p + k * top] = steps[p]
                nub.append(ub[i])
                if model is not None:
                    w.append(model[gi][i])
        out.append((nprogs, nsteps, nub))
        out_model.append(w)
    return out, (out_model if model is not None else None)


def assign_groups(weights, n, min_ranks):
    """Rank groups for interleaved programs, as planRankGroups (src/study/stage.cpp) forms them:
    G = min(programs, n // min_ranks) groups; programs dealt out costliest first to the group with
    the least cost so far (lowest index on ties); ranks shared out in proportion to the groups' costs
    (at least one each; too many: taken from the most over their share, too few: given to the most
    under it). Returns (group per program, ranks per group), or None for fewer than two groups."""
    progs = len(weights)
    g = min(progs, n // max(1, min_ranks))
    if g < 2:
        return None
    load = [0.0] * g
    group_of = [0] * progs
    for p in sorted(range(progs), key=lambda p: -weights[p]):  # stable: ties in program order
        j = min(range(g), key=lambda j: (load[j], j))
        group_of[p] = j
        load[j] += weights[p]
    total = sum(load)
    share = [n * w / total if total > 0 else n / g for w in load]
    ranks = [max(1, int(x)) for x in share]

    def pick(sign):
        best = None
        for j in range(g):
            if sign > 0 and ranks[j] <= 1:
                continue
            if best is None or sign * (ranks[j] - share[j]) > sign * (ranks[best] - share[best]):
                best = j
        return best
    while sum(ranks) > n:
        ranks[pick(+1)] -= 1
    while sum(ranks) < n:
        ranks[pick(-1)] += 1
    return group_of, ranks


def model_weights(run_dir, grids):
    """The weights src/stages/reach/reach_grid_results.cpp gives the searches: one plus the reachable poses, a
    tenth of them for an arm of at most six joints (defaults::kSearchWeightNonRedundant), from the recorded run's
    summary.json and designs.json (its reachable poses after the search, close to the sweep's)."""
    import json
    import os
    summary = json.load(open(os.path.join(run_dir, "summary.json")))
    designs = json.load(open(os.path.join(run_dir, "designs.json")))
    out = []
    for (progs, _, _), g in zip(grids, summary["reach"]["grids"]):
        out.append([1 + g["designs"][p]["reachable"] * (1.0 if designs[p]["dof"] > 6 else 0.1) for p in progs])
    return out


def simulate_grouped_searches(grids, n, min_ranks, latency, bandwidth, apply, serial_search, weights_kind,
                              model=None):
    """Seconds of the grids' map searches on n ranks in rank groups (each group runs its programs'
    steps among its own ranks, then every program's final map goes to every rank), and the same
    searches with every rank in every step (the combined steps); serial_search: the searches' own
    bookkeeping in the 1-process run, split evenly over the programs."""
    grouped = flat = 0.0
    nprog = sum(len(p) for p, _, _ in grids)
    for gi, (progs, steps, unit_bytes) in enumerate(grids):
        per_prog_serial = serial_search / max(1, nprog)
        nsteps = max(len(steps[p]) for p in progs)
        combined = [[c for p in progs if k < len(steps[p]) for c in steps[p][k]] for k in range(nsteps)]
        flat_t = sum(simulate_step(st, n, latency, bandwidth, False, apply) for st in combined) + \
            per_prog_serial * len(progs)
        flat += flat_t
        if weights_kind == "model":
            w = model[gi]
        else:
            w = [sum(c for st in steps[p] for c, _ in st) if weights_kind == "oracle" else 1.0 for p in progs]
        a = assign_groups(w, n, min_ranks)
        if a is None:
            grouped += flat_t
            continue
        group_of, ranks = a
        times = []
        for j, nj in enumerate(ranks):
            mine = [p for i, p in enumerate(progs) if group_of[i] == j]
            ks = max(len(steps[p]) for p in mine)
            t = sum(simulate_step([c for p in mine if k < len(steps[p]) for c in steps[p][k]], nj, latency,
                                  bandwidth, False, apply) for k in range(ks))
            times.append(t + per_prog_serial * len(mine))
        # Each program sends the rows its search changed: at most its whole map (its units' bytes) and
        # at most what its steps sent.
        total_bytes = sum(min(unit_bytes[i], sum(b for st in steps[p] for _, b in st)) for i, p in enumerate(progs))
        exchange = math.log2(n) * latency * len(ranks) + total_bytes / bandwidth + total_bytes * apply
        grouped += max(times) + exchange
    return grouped, flat


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("csv")
    ap.add_argument("--replicate", type=int, default=1, help="batches repeated R times (more variants)")
    ap.add_argument("--scale", type=float, default=1.0, help="unit cost factor")
    ap.add_argument("--group", type=int, default=1, help="units of G consecutive recorded units (a coarser grain)")
    ap.add_argument("--serial-total", type=float, default=0.0,
                    help="serial seconds of the recorded run outside the units (wall of a 1-thread run minus "
                         "the sum of unit costs), spread evenly over its batches")
    ap.add_argument("--ranks", default="1,2,16,32,64,128,256,512,1024")
    ap.add_argument("--latency", type=float, default=5e-6)
    ap.add_argument("--service", type=float, default=5e-6)
    ap.add_argument("--poll", type=float, default=5e-4)
    ap.add_argument("--bandwidth", type=float, default=5e9)
    ap.add_argument("--apply", type=float, default=1.1e-9,
                    help="seconds per byte a rank spends applying the others' results (unit loads, a step's "
                         "adopted rows): measured 1.1 ns/byte, every rank of `mpirun -np 2` applied its ~92 MB "
                         "of the other's search rows in 0.10 s (compare_designs, 2026-11-26)")
    ap.add_argument("--single", action="store_true", help="one unit per hand-out instead of guided chunks")
    ap.add_argument("--unshared", action="store_true",
                    help="every rank computes every shared step (the runner before the search was shared)")
    ap.add_argument("--one-pool", action="store_true",
                    help="what-if: every batch of the study handed out from one pool (no barrier between "
                         "batches) and the batches' serial work spread over the ranks")
    ap.add_argument("--interleaved", action="store_true",
                    help="the replicas' designs join the recorded combined steps (a record of interleaved searches)")
    ap.add_argument("--bounds", action="store_true",
                    help="also print, per rank count, the shared steps' ideal share (their work / N), the bound "
                         "set by their grain (sum over steps of max(costliest chunk, work / N)) and round-robin "
                         "placement (sum over steps of the busiest rank's chunks), no latency, no serial work")
    ap.add_argument("--ceiling", action="store_true",
                    help="also print, per rank count, a lower bound on the makespan of any schedule whatever: the "
                         "serial rest (--serial-total; rank 0 runs it, it writes the files) plus the larger of the "
                         "work / N and the longest chain of pieces that must run one after another; and the serial "
                         "rest at most that 80 %% efficiency allows with a perfect schedule")
    ap.add_argument("--groups", type=int, default=0, metavar="R",
                    help="also print the map searches alone in rank groups of at least R ranks (each group runs "
                         "some designs' searches on its ranks, then the final maps go to every rank) against "
                         "every rank in every step; needs a record with the part column")
    ap.add_argument("--serial-search", type=float, default=0.0,
                    help="seconds of the serial rest that are the searches' own bookkeeping (with --groups: "
                         "a group repeats only its programs' share)")
    ap.add_argument("--group-weights", choices=["model", "oracle", "equal"], default="model",
                    help="programs dealt to groups by armstudy's prediction (model: needs --run-dir), by their "
                         "recorded cost (oracle) or as equals")
    ap.add_argument("--run-dir", help="the recorded run's output folder (summary.json, designs.json) for "
                                      "--group-weights model")
    ap.add_argument("--pool-per-grid", action="store_true",
                    help="the unit batches of a grid's designs (and their replicas) handed out from one pool")
    a = ap.parse_args()

    phases = replicate(load_phases(a.csv, a.scale, a.group), a.replicate, a.interleaved)
    if a.pool_per_grid:
        phases = pool_per_grid(phases)
    batches = [items for kind, items in phases if kind == "units"]
    steps = [items for kind, items in phases if kind != "units"]
    # Every rank applies a search or audit step's rows; a files loop sends only the files' names
    # (the rank that renders a piece writes its files in the chunk's recorded cost).
    step_apply = [0.0 if kind == "files" else a.apply for kind, _ in phases if kind != "units"]
    serial = a.serial_total * a.replicate / max(1, len(batches))
    units = sum(len(b) for b in batches)
    work = sum(c for b in batches for c, _ in b)
    step_work = sum(c for st in steps for c, _ in st)
    t1 = work + step_work + serial * len(batches)
    costs = sorted(c for b in batches for c, _ in b)
    print(f"{len(batches)} batches, {units} units, unit cost median {costs[len(costs) // 2] * 1e3:.1f} ms, "
          f"max {costs[-1] * 1e3:.1f} ms, units per batch {min(len(b) for b in batches)}..{max(len(b) for b in batches)}; "
          f"{len(steps)} shared steps; T1 = {t1:.1f} s (units {work:.1f} s, shared steps {step_work:.1f} s, "
          f"serial {serial * len(batches):.1f} s)")
    print(f"latency {a.latency * 1e6:.0f} us, hand-out service {a.service * 1e6:.0f} us, idle poll <= {a.poll * 1e6:.0f} us, "
          f"bandwidth {a.bandwidth / 1e9:.1f} GB/s, applying {a.apply * 1e9:.1f} ns/byte, {'one unit' if a.single else 'guided chunks'} per hand-out, "
          f"steps {'repeated on every rank' if a.unshared else 'shared'}")
    if a.bounds:
        print("| ranks | steps: ideal share [s] | grain bound [s] | round-robin [s] | steps' efficiency at best | as placed |")
        print("|---:|---:|---:|---:|---:|---:|")
        for n in [int(x) for x in a.ranks.split(",")]:
            ideal = step_work / n
            grain = sum(max(max(c for c, _ in st), sum(c for c, _ in st) / n) for st in steps)
            rr = 0.0
            for st in steps:
                load = [0.0] * n
                for k, (c, _) in enumerate(st):
                    load[k % n] += c
                rr += max(load)
            print(f"| {n} | {ideal:.2f} | {grain:.2f} | {rr:.2f} | {100 * ideal / grain:.0f} % | {100 * ideal / rr:.0f} % |")
    if a.ceiling:
        chain, name = load_chains(a.csv, a.scale)
        w = work + step_work
        print(f"Any schedule: longest chain {chain:.3f} s ({name}); work {w:.1f} s; serial rest {a.serial_total:.2f} s")
        print("| ranks | work / N [s] | bound on the makespan [s] | bound on the efficiency | serial rest allowed for 80 % [s] |")
        print("|---:|---:|---:|---:|---:|")
        for n in [int(x) for x in a.ranks.split(",")]:
            s_tot = a.serial_total * a.replicate
            bound = s_tot + max(w / n, chain)
            # (w + s) / (n (s + max(w / n, chain))) >= 0.8  <=>  s <= (w - 0.8 n max(..)) / (0.8 n - 1)
            allowed = (w - 0.8 * n * max(w / n, chain)) / (0.8 * n - 1) if n > 1 else float("inf")
            print(f"| {n} | {w / n:.3f} | {bound:.3f} | {100 * (w + s_tot) / (n * bound):.0f} % | "
                  f"{allowed:.3f} |" if allowed > 0 else f"| {n} | {w / n:.3f} | {bound:.3f} | "
                  f"{100 * (w + s_tot) / (n * bound):.0f} % | none |")
    if a.groups:
        grids = load_search_parts(a.csv, a.scale)
        model = model_weights(a.run_dir, grids) if a.group_weights == "model" else None
        grids, model = replicate_grids(grids, model, a.replicate if a.interleaved else 1)
        print(f"map searches of {sum(len(p) for p, _, _ in grids)} programs in {len(grids)} grids, rank groups of "
              f">= {a.groups} ranks ({a.group_weights} weights), search bookkeeping {a.serial_search:.2f} s:")
        print("| ranks | searches, every rank in every step [s] | in rank groups [s] |")
        print("|---:|---:|---:|")
        grouped = {}
        for n in [int(x) for x in a.ranks.split(",")]:
            g, fl = simulate_grouped_searches(grids, n, a.groups, a.latency, a.bandwidth, a.apply,
                                              a.serial_search * (a.replicate if a.interleaved else 1),
                                              a.group_weights, model)
            grouped[n] = g - fl  # the makespan's change
            print(f"| {n} | {fl:.2f} | {g:.2f} |")
        print("The whole study (below) with the searches in rank groups:")
    print("| ranks | makespan [s] | speed-up | efficiency | master load | hand-outs/s (peak batch) | in shared steps |")
    print("|---:|---:|---:|---:|---:|---:|---:|")
    for n in [int(x) for x in a.ranks.split(",")]:
        step_time = sum(simulate_step(st, n, a.latency, a.bandwidth, a.unshared, ap) for st, ap in zip(steps, step_apply))
        if a.one_pool:
            pool = [u for b in batches for u in b]
            t, mb, h = simulate_batch(pool, n, a.latency, a.service, a.poll, a.bandwidth, a.single, a.apply)
            # The serial tasks (one per batch, equal) spread over the ranks.
            total = t + serial * math.ceil(len(batches) / n) + step_time
            print(f"| {n} | {total:.2f} | {t1 / total:.1f} | {100 * t1 / (n * total):.0f} % | {100 * mb / total:.2f} % | "
                  f"{h / t:.0f} | {100 * step_time / total:.0f} % |")
            continue
        total = busy = 0.0
        peak = 0.0
        for b in batches:
            t, mb, h = simulate_batch(b, n, a.latency, a.service, a.poll, a.bandwidth, a.single, a.apply)
            total += t + serial
            busy += mb
            if t > 0:
                peak = max(peak, h / t)
        total += step_time
        if a.groups:
            total += grouped[n]
            step_time += grouped[n]
        print(f"| {n} | {total:.2f} | {t1 / total:.1f} | {100 * t1 / (n * total):.0f} % | {100 * busy / total:.2f} % | "
              f"{peak:.0f} | {100 * step_time / total:.0f} % |")


if __name__ == "__main__":
    main()
