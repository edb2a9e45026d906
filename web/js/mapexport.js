// The phase map as a file: one standalone SVG with the axes, the predicted regions (an image of
// their cells), the markers as vectors (drawn by the canvas's own drawPointMark through
// SvgPathContext), the overlays and the legend; PNG is that SVG rendered at twice its size.
import { svgEl } from './plot.js';
import { SvgPathContext } from './svgcanvas.js';
import { drawMarker } from './classes.js';
import { drawPointMark } from './points.js';

const SVG_NS = 'http://www.w3.org/2000/svg';
// Style properties the page's CSS gives the plot's SVG (classes .ticklabel, .gridline, ...),
// copied onto each element so the file looks the same without the stylesheet.
const STYLE_PROPS = ['fill', 'fill-opacity', 'stroke', 'stroke-width', 'stroke-dasharray', 'stroke-opacity',
  'stroke-linejoin', 'paint-order', 'opacity', 'font-family', 'font-size', 'font-weight', 'font-style', 'letter-spacing'];
const LEGEND_W = 230;
const PNG_SCALE = 2;

// A copy of an SVG subtree with its computed styles written inline.
function inlined(node) {
  const copy = node.cloneNode(true);
  const src = [node, ...node.querySelectorAll('*')];
  const dst = [copy, ...copy.querySelectorAll('*')];
  for (let k = 0; k < src.length; k++) {
    const cs = getComputedStyle(src[k]);
    const style = STYLE_PROPS.map((p) => `${p}:${cs.getPropertyValue(p)}`).join(';');
    dst[k].setAttribute('style', style);
    dst[k].removeAttribute('class');
  }
  return copy;
}

// The standalone SVG element of the map. figure: { plot, markers: [{cat, x, y, r, progress,
// fade, ring, split, unsettled, human, job}], regions: {x0, y0, x1, y1, image} | null, legend: [{cat,
// name, count}, {mark: {cat, fade, ring, split, unsettled}, name} or {color: [r, g, b], name}],
// title, note: lines of text under the legend, drawMark(ctx, marker): how a marker is drawn
// (drawPointMark unless given; the Plots page's) }. A marker with a job carries it (data-job).
export function mapSvg(figure) {
  const { plot, markers, regions, legend, title, note } = figure;
  const w = Number(plot.svg.getAttribute('width')), h = Number(plot.svg.getAttribute('height'));
  const rowH = 22;
  const height = Math.max(h, 60 + legend.length * rowH + 15 * (note || []).length);
  const svg = document.createElementNS(SVG_NS, 'svg');
  svg.setAttribute('xmlns', SVG_NS);
  svg.setAttribute('width', w + LEGEND_W);
  svg.setAttribute('height', height);
  svg.setAttribute('viewBox', `0 0 ${w + LEGEND_W} ${height}`);
  svgEl('title', {}, svg).textContent = title;
  svgEl('rect', { x: 0, y: 0, width: w + LEGEND_W, height, fill: '#ffffff' }, svg);
  // Axes, grid and frame (the plot's back SVG), then what the canvas holds, then the overlays.
  const back = inlined(plot.svg);
  for (const t of back.querySelectorAll('title')) t.remove();
  const axes = svgEl('g', { 'data-layer': 'axes' }, svg);
  axes.append(...back.childNodes);
  const clipId = 'plot-area';
  svgEl('rect', { x: plot.m.l, y: plot.m.t, width: plot.pw, height: plot.ph }, svgEl('clipPath', { id: clipId }, svgEl('defs', {}, svg)));
  const area = svgEl('g', { 'clip-path': `url(#${clipId})` }, svg);
  if (regions) {
    svgEl('image', {
      'data-layer': 'regions', x: plot.m.l + regions.x0, y: plot.m.t + regions.y0, width: regions.x1 - regions.x0,
      height: regions.y1 - regions.y0, preserveAspectRatio: 'none', href: regions.image.toDataURL('image/png'),
    }, area);
  }
  const marks = svgEl('g', { 'data-layer': 'markers' }, area);
  const drawMark = figure.drawMark || drawPointMark;
  for (const m of markers) {
    const g = svgEl('g', m.job ? { 'data-cat': m.cat, 'data-job': m.job } : { 'data-cat': m.cat }, marks);
    drawMark(new SvgPathContext(g), { ...m, x: plot.m.l + m.x, y: plot.m.t + m.y });
  }
  // The frame again over the background, as on the page (the canvas sits inside it).
  svgEl('rect', { x: plot.m.l, y: plot.m.t, width: plot.pw, height: plot.ph, fill: 'none', stroke: '#1d2433', 'stroke-width': 1 }, svg);
  const over = inlined(plot.over);
  const overlays = svgEl('g', { 'data-layer': 'overlays' }, svg);
  overlays.append(...over.childNodes);
  // The legend: a marker and a name per line, with its count.
  const lg = svgEl('g', { 'data-layer': 'legend', 'font-family': 'sans-serif', 'font-size': 13, fill: '#1d2433' }, svg);
  const x0 = w + 12;
  svgEl('text', { x: x0, y: 30, 'font-weight': 600 }, lg).textContent = 'Legend';
  legend.forEach((item, k) => {
    const y = 52 + k * rowH;
    if (item.color) {
      svgEl('rect', { x: x0 + 2, y: y - 10, width: 14, height: 11, fill: `rgb(${item.color.join(',')})`, stroke: '#d5d9e0' }, lg);
    } else if (item.mark) {
      const g = svgEl('g', { 'data-cat': item.mark.cat }, lg);
      drawPointMark(new SvgPathContext(g), { ...item.mark, x: x0 + 9, y: y - 4, r: 6 });
    } else {
      const g = svgEl('g', { 'data-cat': item.cat }, lg);
      drawMarker(new SvgPathContext(g), item.cat, x0 + 9, y - 4, 6, 0.6);
    }
    svgEl('text', { x: x0 + 24, y }, lg).textContent = item.name;
    const c = svgEl('text', { x: w + LEGEND_W - 14, y, 'text-anchor': 'end' }, lg);
    c.textContent = item.count === undefined ? '' : String(item.count);
  });
  (note || []).forEach((line, k) => {
    const t = svgEl('text', { x: x0, y: 52 + legend.length * rowH + 8 + 15 * k, 'font-size': 11, fill: '#4b5563' }, lg);
    t.textContent = line;
  });
  return svg;
}

export function svgText(svg) {
  return `<?xml version="1.0" encoding="UTF-8"?>\n${new XMLSerializer().serializeToString(svg)}\n`;
}

// The SVG rendered to a PNG blob at PNG_SCALE times its size.
export async function pngBlob(svg) {
  const w = Number(svg.getAttribute('width')), h = Number(svg.getAttribute('height'));
  const url = URL.createObjectURL(new Blob([svgText(svg)], { type: 'image/svg+xml' }));
  try {
    const img = new Image();
    img.src = url;
    await img.decode();
    const c = document.createElement('canvas');
    c.width = w * PNG_SCALE; c.height = h * PNG_SCALE;
    const ctx = c.getContext('2d');
    ctx.scale(PNG_SCALE, PNG_SCALE);
    ctx.drawImage(img, 0, 0, w, h);
    return await new Promise((resolve, reject) => c.toBlob((b) => (b ? resolve(b) : reject(new Error('PNG encoding failed'))), 'image/png'));
  } finally {
    URL.revokeObjectURL(url);
  }
}

// Saves a blob under a file name through a download link.
export function download(blob, name) {
  const a = document.createElement('a');
  a.href = URL.createObjectURL(blob);
  a.download = name;
  document.body.append(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(a.href), 10000);
}
