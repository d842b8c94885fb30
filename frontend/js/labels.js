// Site labels placed without collision, as a planner reads a map of 20 sites (issue 25 item 4): each label goes
// beside its marker where it covers no other label and no marker, else farther out on a leader line; one that fits
// nowhere is left out (its marker still names it on hover). Pure: no DOM here, so the map and the PNG share it.

const DIRECTIONS = [[1, 0], [-1, 0], [0, -1], [0, 1], [1, -1], [1, 1], [-1, -1], [-1, 1]]; // right first, as before
const RINGS = [1, 2.5, 4]; // how far out a label may go, in gaps beyond the marker: past the first, a leader line

/** Boxes overlap (x, y the top-left corner, w, h the size; a margin of `pad` px kept round each). */
const overlaps = (a, b, pad) => a.x < b.x + b.w + pad && b.x < a.x + a.w + pad
  && a.y < b.y + b.h + pad && b.y < a.y + a.h + pad;

/**
 * Place labels in order of `items` ({x, y}: the marker's point in px; w, h: the label's size). Returns for each
 * item null (no room) or {x, y, leader}: the label's top-left corner, and [x0, y0, x1, y1] from the marker's edge to
 * the label when it stands off (else null). `markerPx`: a marker's half size, every marker an obstacle; `gapPx`:
 * the space between a marker and a label beside it; `bounds` {x, y, w, h}: labels stay inside it.
 */
export function placeLabels(items, { markerPx = 7, gapPx = 5, padPx = 2, bounds = null } = {}) {
  const taken = items.map((it) => ({ x: it.x - markerPx, y: it.y - markerPx, w: 2 * markerPx, h: 2 * markerPx }));
  return items.map((it) => {
    for (const [k, ring] of RINGS.entries()) {
      const reach = markerPx + gapPx * ring;
      for (const [dx, dy] of DIRECTIONS) {
        const box = {
          x: dx > 0 ? it.x + reach : dx < 0 ? it.x - reach - it.w : it.x - it.w / 2,
          y: dy > 0 ? it.y + reach : dy < 0 ? it.y - reach - it.h : it.y - it.h / 2,
          w: it.w, h: it.h,
        };
        if (bounds && (box.x < bounds.x || box.y < bounds.y || box.x + box.w > bounds.x + bounds.w
                       || box.y + box.h > bounds.y + bounds.h)) continue;
        if (taken.some((t) => overlaps(box, t, padPx))) continue;
        taken.push(box);
        const leader = k === 0 ? null : [it.x + dx * markerPx, it.y + dy * markerPx,
                                         clamp(it.x, box.x, box.x + box.w), clamp(it.y, box.y, box.y + box.h)];
        return { x: box.x, y: box.y, leader };
      }
    }
    return null;
  });
}

const clamp = (v, lo, hi) => Math.max(lo, Math.min(hi, v));
