# The render time, in seconds, of nori's "Done in ..." line: "Done in 840 ms (",
# "8.31 s (", "6 min 43 s (", "1 h 02 min (". Shared by scripts/bench_cycles.sh and
# scripts/bench_pbrt.sh; prints nothing for a render that did not finish.
/^Done in / {
    n = split(substr($0, 9, index($0, " (") - 9), f, " "); t = 0
    for (i = 1; i < n; i += 2) {
        unit = f[i + 1] == "ms" ? 0.001 : f[i + 1] == "s" ? 1 : f[i + 1] == "min" ? 60 : 3600
        t += f[i] * unit
    }
    print t
}
