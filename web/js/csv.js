// Parses a numeric CSV with a header line (frames.csv) into {columns: {name: Float64Array}, rows}.
export function parseCsv(text) {
  const lines = text.split(/\r?\n/).filter((l) => l.trim() !== '');
  if (lines.length === 0) return { names: [], columns: {}, rows: 0 };
  const names = lines[0].split(',').map((s) => s.trim());
  const columns = Object.fromEntries(names.map((n) => [n, new Float64Array(lines.length - 1)]));
  for (let i = 1; i < lines.length; i++) {
    const cells = lines[i].split(',');
    names.forEach((n, j) => { columns[n][i - 1] = cells[j] === undefined ? NaN : Number(cells[j]); });
  }
  return { names, columns, rows: lines.length - 1 };
}
