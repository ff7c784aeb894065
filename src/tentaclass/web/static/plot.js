// Drawing on canvases: a view maps world coordinates (y up) to canvas pixels (y down).

export function identityView() {
  return { s: 1, tx: 0, ty: 0 };
}

// A view that fits all the points into the canvas with a margin.
export function fitView(canvas, pointSets, margin = 30) {
  const all = pointSets.flat();
  const xs = all.map((p) => p[0]);
  const ys = all.map((p) => p[1]);
  const x0 = Math.min(...xs), x1 = Math.max(...xs);
  const y0 = Math.min(...ys), y1 = Math.max(...ys);
  const span = Math.max(x1 - x0, y1 - y0, 1e-9);
  const s = (Math.min(canvas.width, canvas.height) - 2 * margin) / span;
  return {
    s,
    tx: canvas.width / 2 - (s * (x0 + x1)) / 2,
    ty: canvas.height / 2 + (s * (y0 + y1)) / 2,
  };
}

export function toCanvas(view, p) {
  return [view.s * p[0] + view.tx, -view.s * p[1] + view.ty];
}

export function toWorld(view, c) {
  return [(c[0] - view.tx) / view.s, -(c[1] - view.ty) / view.s];
}

export function polyline(ctx, view, pts, { color = "#222", width = 1, closed = false, dash = [] } = {}) {
  if (pts.length === 0) return;
  ctx.save();
  ctx.strokeStyle = color;
  ctx.lineWidth = width;
  ctx.setLineDash(dash);
  ctx.beginPath();
  pts.forEach((p, i) => {
    const [x, y] = toCanvas(view, p);
    if (i === 0) ctx.moveTo(x, y);
    else ctx.lineTo(x, y);
  });
  if (closed) ctx.closePath();
  ctx.stroke();
  ctx.restore();
}

export function dots(ctx, view, pts, { color = "#222", radius = 3 } = {}) {
  ctx.save();
  ctx.fillStyle = color;
  for (const p of pts) {
    const [x, y] = toCanvas(view, p);
    ctx.beginPath();
    ctx.arc(x, y, radius, 0, 2 * Math.PI);
    ctx.fill();
  }
  ctx.restore();
}

// Joint angles against joint index, with the zero line and +-pi/2 marks.
export function plotAngles(canvas, angles) {
  const ctx = canvas.getContext("2d");
  const w = canvas.width, h = canvas.height, pad = 24;
  ctx.clearRect(0, 0, w, h);
  ctx.font = "11px sans-serif";
  ctx.fillStyle = "#555";
  const lim = Math.max(Math.PI / 2, ...angles.map((a) => Math.abs(a)));
  const y = (a) => h / 2 - (a / lim) * (h / 2 - pad / 2);
  const x = (i) => pad + (angles.length > 1 ? (i / (angles.length - 1)) * (w - 2 * pad) : 0);
  ctx.strokeStyle = "#ccc";
  for (const a of [0, Math.PI / 2, -Math.PI / 2]) {
    ctx.beginPath();
    ctx.moveTo(pad, y(a));
    ctx.lineTo(w - pad, y(a));
    ctx.stroke();
  }
  ctx.fillText("+π/2", 0, y(Math.PI / 2) + 4);
  ctx.fillText("0", 8, y(0) + 4);
  ctx.fillText("−π/2", 0, y(-Math.PI / 2) + 4);
  ctx.fillText("joint", w - pad - 20, h - 2);
  if (angles.length === 0) return;
  ctx.strokeStyle = "#4a7fc1";
  ctx.lineWidth = 1.5;
  ctx.beginPath();
  angles.forEach((a, i) => (i === 0 ? ctx.moveTo(x(i), y(a)) : ctx.lineTo(x(i), y(a))));
  ctx.stroke();
  ctx.fillStyle = "#4a7fc1";
  angles.forEach((a, i) => ctx.fillRect(x(i) - 1.5, y(a) - 1.5, 3, 3));
}
