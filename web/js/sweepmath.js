// The grid arithmetic of the server's planner (server/plan/planner.cpp, expand_axis), mirrored so the
// dashboard can list phi values of sweeps and count a sweep's jobs before it is submitted.

export function roundSignificant(v) {
  return Number.isFinite(v) && v !== 0 ? Number(v.toPrecision(12)) : v;
}

// Values of an axis: a number, an array, or {min, max, n, scale}. Throws nothing: [] if invalid.
export function expandAxis(axis) {
  if (typeof axis === 'number') return [axis];
  if (Array.isArray(axis)) return axis.filter((v) => typeof v === 'number');
  if (!axis || typeof axis !== 'object') return [];
  const { min: lo, max: hi, n } = axis;
  const log = axis.scale === 'log';
  if (!Number.isFinite(lo) || !Number.isFinite(hi) || !Number.isInteger(n) || n < 1 || lo > hi || (log && lo <= 0)) return [];
  const out = [];
  for (let i = 0; i < n; i++) {
    const t = n === 1 ? 0 : i / (n - 1);
    out.push(roundSignificant(log ? lo * (hi / lo) ** t : lo + (hi - lo) * t));
  }
  out[0] = lo;
  out[n - 1] = n === 1 ? lo : hi;
  return out;
}

// The phi values a sweep request covers.
export function sweepPhis(request) {
  if (!request) return [];
  if (Array.isArray(request.points)) return request.points.map((p) => p.phi).filter(Number.isFinite);
  return expandAxis(request.phi ?? 0.4);
}
