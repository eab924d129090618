#!/usr/bin/env python3
"""Replays "the embedding head wakes, the cnn spotter confirms" over score dumps.

Input: the files `marvin-kws-eval --dump-scores PREFIX` writes on a synthetic track
(PREFIX.scores.tsv, PREFIX.cnn.tsv, PREFIX.track.tsv). The rule, streaming: at every 80 ms
step where the first head's score has been at or over THRESHOLD for STEPS steps in a row,
Marvin wakes if the cnn spotter's posterior reached CONFIRM in the last BACK seconds (0:
no confirmation, the shipped rule), at most once per refractory period (2 s). A detection
counts for a keyword when it ends inside the keyword or up to 1.25 s after it, as in
marvin-kws-eval; every other one is a false accept.

    tools/kws/replay_cascade.py /tmp/s1001 /tmp/s1002

prints, per track, the shipped rule, the lowest miss rate with at most one false accept, and
the settings that stay at one or fewer on every track given. Python 3, nothing else.
"""
import bisect
import itertools
import sys

REFRACTORY = 32000  # samples at 16 kHz
TOLERANCE = 20000   # a detection may end this long after the keyword


def load(prefix):
    head = []
    with open(prefix + ".scores.tsv") as f:
        for line in f:
            h, end, score = line.split("\t")
            if h == "0":
                head.append((int(end), float(score)))
    with open(prefix + ".cnn.tsv") as f:
        cnn = [(int(a), float(b)) for a, b in (line.split("\t") for line in f)]
    keywords = []
    with open(prefix + ".track.tsv") as f:
        for line in f:
            kind, begin, end = line.split("\t")[:3]
            if kind == "keyword":
                keywords.append((int(begin), int(end)))
    return head, cnn, keywords


def detections(head, cnn, steps, threshold, confirm, back):
    cnn_ends = [e for e, _ in cnn]
    cnn_scores = [s for _, s in cnn]
    ends, run = [], 0
    for end, score in head:
        run = run + 1 if score >= threshold else 0
        if run < steps or (ends and end - ends[-1] < REFRACTORY):
            continue
        if confirm > 0:
            lo = bisect.bisect_left(cnn_ends, end - back)
            hi = bisect.bisect_right(cnn_ends, end)
            if hi == lo or max(cnn_scores[lo:hi]) < confirm:
                continue
        ends.append(end)
    return ends


def score(ends, keywords):
    found = [False] * len(keywords)
    false_accepts = 0
    for e in ends:
        for k, (begin, end) in enumerate(keywords):
            if not found[k] and begin <= e <= end + TOLERANCE:
                found[k] = True
                break
        else:
            false_accepts += 1
    return 1.0 - sum(found) / len(keywords), false_accepts


def main(prefixes):
    tracks = [load(p) for p in prefixes]
    grid = itertools.product((1, 2, 3, 4, 5), (0.3, 0.5, 0.7, 0.8, 0.9, 0.95),
                             (0, 0.1, 0.3, 0.5, 0.7, 0.8, 0.9, 0.95, 0.98), (16000,))
    results = {}
    for setting in grid:
        results[setting] = [score(detections(h, c, *setting), k) for h, c, k in tracks]

    def show(setting):
        steps, threshold, confirm, back = setting
        figures = ", ".join(f"{100 * m:.2f} % missed, {fa} FA" for m, fa in results[setting])
        rule = f"{steps} steps >= {threshold}" + (
            f", cnn >= {confirm} in the last {back / 16000:.1f} s" if confirm else "")
        print(f"  {rule}: {figures}")

    print("shipped rule (4 steps 0.8, no confirmation):")
    show((4, 0.8, 0, 16000))
    for i, prefix in enumerate(prefixes):
        best = min((r[i][0], s) for s, r in results.items() if r[i][1] <= 1)
        print(f"best with at most one false accept on {prefix}:")
        show(best[1])
    joint = sorted((max(m for m, _ in r), s) for s, r in results.items()
                   if all(fa <= 1 for _, fa in r))
    print("best with at most one false accept on every track:")
    for _, s in joint[:3]:
        show(s)


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit("usage: replay_cascade.py PREFIX... (files of marvin-kws-eval --dump-scores)")
    main(sys.argv[1:])
