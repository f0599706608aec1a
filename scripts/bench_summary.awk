# The summary line of a benchmark's configuration, shared by scripts/bench_lights.sh and
# scripts/bench_cycles.sh. Input: one line "TIMES... | ERRORS..." (seconds, then the
# MSE or relMSE of each round); -v baseline=E: the efficiency to compare with (empty: this
# is the baseline). Output: the median time and the range, the mean error ± its standard
# error, the efficiency 1/(median time × mean error), its ratio to the baseline, and the
# efficiency again (for the caller to keep as a baseline).
{
    n = 0; m = 0
    for (i = 1; $i != "|"; ++i) t[++n] = $i
    for (i = i + 1; i <= NF; ++i) e[++m] = $i
    for (i = 2; i <= n; ++i) # insertion sort (POSIX awk has no asort)
        for (j = i; j > 1 && t[j - 1] > t[j]; --j) { x = t[j]; t[j] = t[j - 1]; t[j - 1] = x }
    median = (n % 2) ? t[(n + 1) / 2] : (t[n / 2] + t[n / 2 + 1]) / 2
    mean = 0; for (i = 1; i <= m; ++i) mean += e[i]; mean /= m
    var = 0; for (i = 1; i <= m; ++i) var += (e[i] - mean) ^ 2
    se = (m > 1) ? sqrt(var / (m - 1) / m) : 0
    efficiency = 1 / (median * mean)
    relative = (baseline == "") ? 1 : efficiency / baseline
    printf "%10.2f %5.2f-%-5.2f %12.4e ± %8.2e %12.4g %8.2fx %s\n", median, t[1], t[n], mean, se,
        efficiency, relative, efficiency
}
