/* Places the phase portrait's theory point labels on the frame the browser lays out.
 *
 * The body of a `CustomJS` callback (app.plots.labels, `place_labels`), run when the frame's
 * size, the ranges, the label font, the stop or the drawn data change; not a script of the
 * page. Arguments: `labels` (the LabelSet), `fig` (its figure), `stop` (the stop line, a
 * Span). The label source has the points (`x`, `v`), their text and `centre`, the
 * displacement of the slip arcs' centre (a, 0); this is the one place where a label's
 * position is decided.
 *
 * Each label is tried at positions around its marker: its corners first (the one facing away
 * from the curves through the point first: `preferredCorner`), then its sides, above and
 * below, then the same twice and three times as far. A position costs much when its box
 * leaves the frame or touches another label, a marker or the stop line, a little for each
 * curve that crosses it, and less for being farther; the labels take the positions that
 * cost least together. The result is written into the label
 * source's `align`, `baseline`, `dx`, `dy` in place (the browser's own view of it: nothing is
 * sent to the server), and the label set is drawn again.
 */
// Right after the figure fits its ranges in a paint (equal aspect), static/perf/
// bokeh_paint.js (patch 9) calls this figure's placement itself, so that the paint draws
// the labels where they go; the call for the same ranges that follows the paint then
// finds them placed.
fig._fie_place_labels = place;
if ((cb_obj === fig.x_range || cb_obj === fig.y_range) && labels._fie_placed_for === frameKey()) {
  return;
}
// A release changes the ranges and several sources at once, each a call: they are
// coalesced into one placement, after the update's other changes and before its paint.
if (labels._fie_place_queued) return;
labels._fie_place_queued = true;
queueMicrotask(() => {
  labels._fie_place_queued = false;
  place();
});

// The frame the labels are placed on: ranges and size.
function frameKey() {
  const [xr, yr] = [fig.x_range, fig.y_range];
  let size = "";
  try {
    size = `${fig.inner_width} ${fig.inner_height}`;
  } catch {
    // not laid out yet
  }
  return `${xr.start} ${xr.end} ${yr.start} ${yr.end} ${size}`;
}

function place() {
  const src = labels.source;
  const data = src.data;
  const n = data.x.length;
  let W, H;
  try {
    [W, H] = [fig.inner_width, fig.inner_height];
  } catch {
    return;  // the figure is not laid out yet: its frame size is unset (reading it throws)
  }
  const [xr, yr] = [fig.x_range, fig.y_range];
  labels._fie_placed_for = frameKey();
  const spanx = xr.end - xr.start, spany = yr.end - yr.start;
  if (n === 0 || !(W > 0 && H > 0 && spanx !== 0 && spany !== 0 && isFinite(spanx + spany))) {
    return;
  }
  const sx = (x) => ((x - xr.start) / spanx) * W;
  const sy = (y) => ((yr.end - y) / spany) * H;
  const val = (spec) => (spec != null && typeof spec === "object" ? spec.value : spec);

  // Clearance [px] kept between a label and what it must not touch.
  const CLEAR = 2;
  const HARD = 1e4, OUTSIDE = 10, CROSSING = 4, FARTHER = 15, LATER = 0.1;
  // Positions the search looks at, at most (the first it finds is already a fair one).
  const MAX_NODES = 20000;

  const box = (l, t, r, b) => ({l, t, r, b});
  const hit = (a, b) => a.l < b.r + CLEAR && b.l < a.r + CLEAR && a.t < b.b + CLEAR && b.t < a.b + CLEAR;
  const shown = fig.renderers.filter((r) => r.visible && r.glyph != null);

  // Markers: every scatter's, its half widths from size and line width (a diamond is narrow).
  const markers = [];
  let own = null;  // half width and height of the theory points' markers
  for (const r of shown.filter((r) => r.glyph.type === "Scatter")) {
    const g = r.glyph, rad = (val(g.size) ?? 0) / 2, lw = val(g.line_width) ?? 1;
    if (!(rad > 0)) continue;
    const hw = (val(g.marker) === "diamond" ? rad / 1.5 : rad) + lw / 2, hh = rad + lw / 2;
    if (r.data_source === src) own = {hw, hh};
    const d = r.data_source.data;
    for (let i = 0; i < d.x.length; i++) {
      const x = sx(d.x[i]), y = sy(d.v[i]);
      if (isFinite(x + y)) markers.push(box(x - hw, y - hh, x + hw, y + hh));
    }
  }
  own = own ?? {hw: 6, hh: 8};
  const walls = [];
  if (stop.visible) {
    const x = sx(stop.location), w = stop.line_width / 2;
    if (isFinite(x)) walls.push(box(x - w, 0, x + w, H));
  }

  // Text size as BokehJS measures it (core/util/text: the font's bounding box); one
  // measuring canvas per label set, kept between placements.
  const size = parseFloat(val(labels.text_font_size)) || 12;
  const ctx = (labels._fie_ctx ??= document.createElement("canvas").getContext("2d"));
  ctx.font = `${val(labels.text_font_style) ?? "normal"} ${val(labels.text_font_size)} `
           + `${val(labels.text_font) ?? "helvetica"}`;
  const fm = ctx.measureText("ÅŚg|");
  const th = fm.fontBoundingBoxAscent + fm.fontBoundingBoxDescent;
  const texts = data[labels.text.field] ?? data.name;
  const pad = Math.max(CLEAR + 1, 0.2 * size);
  const widths = [];
  // Where a label's positions can lie (the farthest ring, below): only segments that pass
  // there can cross one.
  const reach = [];
  for (let i = 0; i < n; i++) {
    const x = sx(data.x[i]), y = sy(data.v[i]), w = ctx.measureText(`${texts[i]}`).width;
    widths.push(w);
    const rx = own.hw + pad + 2 * size + w, ry = own.hh + pad + size + th;
    if (isFinite(x + y)) reach.push(box(x - rx, y - ry, x + rx, y + ry));
  }

  // Curves [px]: a position costs for each curve that crosses it. Their segments inside the
  // frame and near a label go into cells of CELL px (a phase path has thousands), so that a
  // position tests only the segments of the cells it covers.
  const CELL = 32, cols = Math.ceil(W / CELL) + 1, rows = Math.ceil(H / CELL) + 1;
  const cells = new Map();  // cell index -> [[curve, x0, y0, x1, y1], ...]
  const cellOf = (x, y) => Math.min(Math.max(Math.floor(y / CELL), 0), rows - 1) * cols
                           + Math.min(Math.max(Math.floor(x / CELL), 0), cols - 1);
  let ncurves = 0;
  for (const r of shown.filter((r) => r.glyph.type === "Line")) {
    const d = r.data_source.data, xs = d[r.glyph.x.field], ys = d[r.glyph.y.field];
    if (xs == null || ys == null) continue;
    const c = ncurves++;
    for (let i = 1; i < xs.length; i++) {
      const x0 = sx(xs[i - 1]), y0 = sy(ys[i - 1]), x1 = sx(xs[i]), y1 = sy(ys[i]);
      if (!isFinite(x0 + y0 + x1 + y1) || Math.max(x0, x1) < 0 || Math.min(x0, x1) > W
          || Math.max(y0, y1) < 0 || Math.min(y0, y1) > H) continue;
      const seg = box(Math.min(x0, x1), Math.min(y0, y1), Math.max(x0, x1), Math.max(y0, y1));
      if (!reach.some((a) => hit(a, seg))) continue;
      const [c0, c1] = [cellOf(Math.min(x0, x1), Math.min(y0, y1)),
                        cellOf(Math.max(x0, x1), Math.max(y0, y1))];
      for (let row = Math.floor(c0 / cols); row <= Math.floor(c1 / cols); row++) {
        for (let col = c0 % cols; col <= c1 % cols; col++) {
          const k = row * cols + col;
          if (!cells.has(k)) cells.set(k, []);
          cells.get(k).push([c, x0, y0, x1, y1]);
        }
      }
    }
  }
  function crossings(b) {  // the curves with a segment through box b
    const found = new Set();
    const [c0, c1] = [cellOf(b.l, b.t), cellOf(b.r, b.b)];
    for (let row = Math.floor(c0 / cols); row <= Math.floor(c1 / cols); row++) {
      for (let col = c0 % cols; col <= c1 % cols; col++) {
        for (const [c, ...s] of cells.get(row * cols + col) ?? []) {
          if (!found.has(c) && crosses(b, s)) found.add(c);
        }
      }
    }
    return found.size;
  }
  function crosses(b, [x0, y0, x1, y1]) {  // Liang-Barsky clipping of a segment to a box
    if (Math.max(x0, x1) < b.l || Math.min(x0, x1) > b.r
        || Math.max(y0, y1) < b.t || Math.min(y0, y1) > b.b) return false;
    let t0 = 0, t1 = 1;
    const dx = x1 - x0, dy = y1 - y0;
    for (const [p, q] of [[-dx, x0 - b.l], [dx, b.r - x0], [-dy, y0 - b.t], [dy, b.b - y0]]) {
      if (p === 0) {
        if (q < 0) return false;
      } else if (p < 0) {
        t0 = Math.max(t0, q / p);
      } else {
        t1 = Math.min(t1, q / p);
      }
      if (t0 > t1) return false;
    }
    return true;
  }

  // The corner each label tries first, away from the curves through its point:
  // - a point on the stick line (off the stop) is labelled above it, written rightwards,
  //   unless it lies beyond the centre (the slip arc leaves its end down to the right);
  // - a point on the stop is labelled left of it (the stop is the motion's right edge), on
  //   the side of the slip arc through it that faces away from the arc: the arc about
  //   (centre, 0) leaves the stop leftwards towards the x axis when the stop lies short of
  //   the centre and away from it beyond, so the label goes above a point of the upper half
  //   beyond the centre (P_CSl of Fig. 5a) and below one short of it; below its point too
  //   when a label on the same level, to its left, is written towards it (the two ends of a
  //   short stick line ran into each other);
  // - the limit point on the x axis (P_lim) is labelled above it, on the side away from the
  //   circle's centre (Fig. 6b: left of the stop; Fig. 7c: right of it).
  // Points whose velocities differ by less than LEVEL of the largest are on one level.
  const LEVEL = 0.03;
  const stopX = stop.visible ? stop.location : Infinity;
  const tiny = 1e-9 * Math.max(1, isFinite(stopX) ? Math.abs(stopX) : 1);
  const vmax = data.v.reduce((m, v) => (isFinite(v) ? Math.max(m, Math.abs(v)) : m), 0);
  const onStop = data.x.map((x) => x >= stopX - tiny);
  function preferredCorner(i) {  // [h, v]: 1 rightwards or above, -1 leftwards or below
    const x = data.x[i], v = data.v[i], c = data.centre[i];
    if (!onStop[i]) return x > c ? [-1, -1] : [1, 1];
    if (Math.abs(v) <= tiny * Math.max(1, vmax)) return [x > c + tiny ? 1 : -1, 1];
    const facing = data.x.some((xo, j) => !onStop[j] && xo < x
                                          && Math.abs(data.v[j] - v) <= LEVEL * vmax);
    return [-1, !facing && v * (x - c) <= 0 ? 1 : -1];
  }

  // Candidate positions of each label and what each costs before the other labels are known.
  const cands = [];
  for (let i = 0; i < n; i++) {
    const x = sx(data.x[i]), y = sy(data.v[i]);
    const w = widths[i];
    const [h0, v0] = preferredCorner(i);
    const list = [];
    const corners = [[h0, v0], [-h0, v0], [h0, -v0], [-h0, -v0]];
    const sides = [[h0, 0], [-h0, 0], [0, v0], [0, -v0]];
    for (let ring = 0; ring < 3; ring++) {
      const ox = own.hw + pad + ring * size, oy = own.hh + pad + ring * 0.5 * size;
      // Next to the marker: level with it (a corner a quarter of the font up or down), or
      // off it diagonally; farther: diagonally.
      const dirs = [...(ring === 0 ? corners.map(([h, v]) => [h, v, 0.25 * size]) : []),
                    ...corners.map(([h, v]) => [h, v, oy]), ...sides.map(([h, v]) => [h, v, oy])];
      dirs.forEach(([h, v, up], k) => {
        const dx = h * ox, dy = v * up;
        const align = h > 0 ? "left" : h < 0 ? "right" : "center";
        const baseline = v > 0 ? "bottom" : v < 0 ? "top" : "middle";
        const ax = x + dx, ay = y - dy;
        const l = h > 0 ? ax : h < 0 ? ax - w : ax - w / 2;
        const t = v > 0 ? ay - th : v < 0 ? ay : ay - th / 2;
        const b = box(l, t, l + w, t + th);
        const outside = Math.max(0, -b.l) + Math.max(0, b.r - W) + Math.max(0, -b.t) + Math.max(0, b.b - H);
        let cost = ring * FARTHER + k * LATER + (outside > 0 ? HARD + OUTSIDE * outside : 0);
        cost += HARD * (markers.filter((m) => hit(b, m)).length + walls.filter((s) => hit(b, s)).length);
        cost += CROSSING * crossings(b);
        list.push({b, cost, align, baseline, dx, dy});
      });
    }
    cands.push(list);
  }

  // The cheapest positions of all labels together: a depth-first search over the labels,
  // each one's positions cheapest first, cut where the cost so far and the least the rest can
  // cost reach the best found (a few labels of some twenty positions: few nodes are visited).
  for (const list of cands) list.sort((p, q) => p.cost - q.cost);
  const least = cands.map((list) => list[0].cost);
  const rest = least.map((_, k) => least.slice(k).reduce((u, v) => u + v, 0)).concat([0]);
  let pick = null, bestCost = Infinity, nodes = 0;
  const chosen = [];
  function search(k, cost) {
    if (k === n) {
      [pick, bestCost] = [chosen.slice(), cost];
      return;
    }
    for (const c of cands[k]) {
      if (cost + c.cost + rest[k + 1] >= bestCost || ++nodes > MAX_NODES) return;
      const overlaps = chosen.slice(0, k).filter((o) => hit(c.b, o.b)).length;
      chosen[k] = c;
      search(k + 1, cost + c.cost + HARD * overlaps);
    }
  }
  search(0, 0);
  const same = pick.every((c, i) => c.align === data.align[i] && c.baseline === data.baseline[i]
                                    && c.dx === data.dx[i] && c.dy === data.dy[i]);
  if (!same) {
    data.align = pick.map((c) => c.align);
    data.baseline = pick.map((c) => c.baseline);
    data.dx = pick.map((c) => c.dx);
    data.dy = pick.map((c) => c.dy);
    // The label set reads its source again on its own change; the source's change would
    // also make the theory points' marker renderer recompute its glyph data and paint the
    // figure once more, for columns it does not draw.
    labels.change.emit();
  }
}
