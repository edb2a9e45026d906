// Small helpers of the dashboard's browser benchmarks (runs_page_bench.mjs, feature_plot_bench.mjs):
// their command-line flags, the median and 90th percentile of a series, a whole number of ms.

// --name value pairs of argv as {name: value}.
export const parseArgs = (argv) => Object.fromEntries(argv.reduce((a, x, i, all) => (x.startsWith('--') ? [...a, [x.slice(2), all[i + 1]]] : a), []));
export const median = (a) => { const s = [...a].sort((x, y) => x - y); const m = s.length >> 1; return s.length % 2 ? s[m] : (s[m - 1] + s[m]) / 2; };
export const p90 = (a) => { const s = [...a].sort((x, y) => x - y); return s[Math.min(s.length - 1, Math.ceil(0.9 * s.length) - 1)]; };
export const f0 = (v) => (Number.isFinite(v) ? v.toFixed(0) : 'none');
