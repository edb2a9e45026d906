// The scene's columns (numerics.geometry, schema/scene.schema.json) as the pages name them: the
// map's Column control and the run table's filter and cells.
export const GEOMETRIES = [
  ['pseudo1d', '2D pseudo-1D'],
  ['pseudo1d_3d', '3D pseudo-1D'],
  ['full2d', 'full 2D'],
];

export function geometryName(g) {
  return GEOMETRIES.find(([k]) => k === g)?.[1] ?? g;
}
