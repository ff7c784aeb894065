// The page: draw (pointer events), wrap (animated link by link), recognise, teach.
import { del, get, post, upload } from "./api.js";
import { dots, fitView, identityView, plotAngles, polyline, toWorld } from "./plot.js";

const $ = (id) => document.getElementById(id);
const canvas = $("draw");
const ctx = canvas.getContext("2d");

// What is on the canvas: the raw stroke, the cleaned outline, the chain.
const state = {
  view: identityView(),
  stroke: [], // world points of the stroke being drawn or last drawn
  drawing: false,
  outline: null, // world outline the chain wraps
  source: null, // {stroke} or {outline}: what the server is asked about
  chain: null, // joint positions of the chain shown
  shownLinks: 0,
  anim: null,
  examples: [], // strokes kept for teaching
};

// Exposed for scripts and tests: the last answers from the server.
window.tentaclass = { state, last: {} };

// Every user action runs through run(): body[data-actions] counts finished actions,
// body[data-idle] is "1" when none is running (scripts and tests wait on these).
let actions = 0;
let pending = 0;
async function run(fn) {
  pending += 1;
  document.body.dataset.idle = "0";
  try {
    await fn();
  } finally {
    pending -= 1;
    actions += 1;
    document.body.dataset.actions = String(actions);
    document.body.dataset.idle = pending === 0 ? "1" : "0";
  }
}

function message(text) {
  const m = $("message");
  m.textContent = text || "";
  m.hidden = !text;
}

function status(text) {
  $("status").textContent = text;
}

// ------------------------------------------------------------------ drawing
function redraw() {
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  const v = state.view;
  if (state.stroke.length && !state.outline) {
    polyline(ctx, v, state.stroke, { color: "#999", width: 2 });
  }
  if (state.outline) {
    if (state.stroke.length) polyline(ctx, v, state.stroke, { color: "#ccc", width: 1 });
    polyline(ctx, v, state.outline, { color: "#222", width: 2, closed: true });
  }
  if (state.chain) {
    const shown = state.chain.slice(0, state.shownLinks + 1);
    polyline(ctx, v, shown, { color: "#d9822b", width: 3 });
    dots(ctx, v, shown, { color: "#8a4b0f", radius: 3 });
    if (shown.length) dots(ctx, v, [shown[0]], { color: "#2a8a2a", radius: 6 });
  }
}

function pointerPoint(e) {
  const r = canvas.getBoundingClientRect();
  const sx = canvas.width / r.width, sy = canvas.height / r.height;
  return toWorld(state.view, [(e.clientX - r.left) * sx, (e.clientY - r.top) * sy]);
}

canvas.addEventListener("pointerdown", (e) => {
  e.preventDefault();
  try {
    canvas.setPointerCapture(e.pointerId);
  } catch (err) {
    // synthetic pointers (scripts) cannot be captured; drawing still works
  }
  stopAnimation();
  state.view = identityView();
  state.drawing = true;
  state.stroke = [pointerPoint(e)];
  state.outline = null;
  state.chain = null;
  message("");
  redraw();
});

canvas.addEventListener("pointermove", (e) => {
  if (!state.drawing) return;
  const events = e.getCoalescedEvents ? e.getCoalescedEvents() : [e];
  for (const ev of events.length ? events : [e]) state.stroke.push(pointerPoint(ev));
  redraw();
});

function endStroke(e) {
  if (!state.drawing) return;
  state.drawing = false;
  try {
    if (canvas.hasPointerCapture(e.pointerId)) canvas.releasePointerCapture(e.pointerId);
  } catch (err) {
    // see pointerdown
  }
  state.source = { stroke: state.stroke };
  run(recognise);
}
canvas.addEventListener("pointerup", endStroke);
canvas.addEventListener("pointercancel", endStroke);

$("clear").addEventListener("click", () => {
  stopAnimation();
  Object.assign(state, { stroke: [], outline: null, chain: null, source: null, view: identityView() });
  message("");
  $("answer").textContent = "draw something";
  $("bars").innerHTML = "";
  $("grasp").textContent = "-";
  $("chainanswer").textContent = "";
  $("angles").value = "";
  plotAngles($("angleplot"), []);
  redraw();
});

// ------------------------------------------------------------- recognition
function showAnswer(answer) {
  const label = answer.label;
  $("answer").textContent = label === "unknown" ? "unknown (nothing fits)" : label;
  $("answer").dataset.label = label;
  const bars = $("bars");
  bars.innerHTML = "";
  const entries = Object.entries(answer.probabilities).sort((a, b) => b[1] - a[1]);
  for (const [name, p] of entries) {
    const row = document.createElement("div");
    row.className = "bar" + (name === label ? " best" : "");
    row.dataset.cls = name;
    row.innerHTML = `<span class="name"></span><span class="fill"></span><span class="pct"></span>`;
    row.querySelector(".name").textContent = name;
    row.querySelector(".fill").style.width = `${Math.round(p * 200)}px`;
    row.querySelector(".pct").textContent = `${(100 * p).toFixed(1)} %`;
    bars.appendChild(row);
  }
}

function failed(err, what) {
  message(`${what}: ${err.message}`);
  status("");
  $("answer").textContent = "-";
  $("answer").dataset.label = "";
  $("bars").innerHTML = "";
}

async function recognise() {
  status("recognising...");
  try {
    const res = await post("/api/classify", state.source);
    window.tentaclass.last.classify = res;
    state.outline = res.outline;
    showAnswer(res);
    redraw();
    await wrapChain();
  } catch (err) {
    failed(err, "cannot use this drawing");
    state.outline = null;
    redraw();
  }
}

// ------------------------------------------------------------------ chain
function chainSettings() {
  const num = (id) => Number($(id).value);
  const body = {
    links: Math.round(num("links")),
    mode: $("mode").value,
    offset: num("offset") / 100,
    noise: num("noise"),
    seed: 0,
  };
  if ($("sizeby").value === "laps") body.laps = num("laps");
  else body.link_length = num("linklen") / 100;
  return body;
}

function stopAnimation() {
  if (state.anim) cancelAnimationFrame(state.anim);
  state.anim = null;
  if (finishAnimation) finishAnimation();
  finishAnimation = null;
}

// Show the chain link by link (1.5 s in all by default); resolves when the last link is drawn
// or the animation is replaced by another.
let finishAnimation = null;
function animate(nLinks) {
  stopAnimation();
  canvas.dataset.anim = "running";
  const t0 = performance.now();
  const total = Number($("speed").value);
  const perLink = total > 0 ? Math.max(4, Math.min(60, total / Math.max(nLinks, 1))) : 0;
  return new Promise((resolve) => {
    finishAnimation = resolve;
    const step = (t) => {
      state.shownLinks = perLink > 0 ? Math.min(nLinks, Math.floor((t - t0) / perLink) + 1) : nLinks;
      canvas.dataset.links = String(state.shownLinks);
      redraw();
      if (state.shownLinks < nLinks) state.anim = requestAnimationFrame(step);
      else {
        state.anim = null;
        canvas.dataset.anim = "done";
        finishAnimation = null;
        resolve();
      }
    };
    state.anim = requestAnimationFrame(step);
  });
}

function showChain(angles, joints, grasp) {
  state.chain = joints;
  $("grasp").textContent =
    `${grasp.state}, ${grasp.laps.toFixed(2)} laps, approach ${grasp.offset_links} links`;
  $("grasp").dataset.state = grasp.state;
  $("angles").value = angles.map((a) => a.toFixed(6)).join(", ");
  plotAngles($("angleplot"), angles);
  return animate(joints.length - 1);
}

// Only the latest wrap request is shown: answers to older ones are dropped.
let wrapSeq = 0;
async function wrapChain() {
  if (!state.outline) return;
  const mine = ++wrapSeq;
  status("wrapping...");
  try {
    const res = await post("/api/wrap", { outline: state.outline, ...chainSettings() });
    if (mine !== wrapSeq) return;
    window.tentaclass.last.wrap = res;
    $("chainanswer").textContent = res.label
      ? `; from the chain's angles: ${res.label}${res.full_lap ? "" : " (no full lap)"}`
      : "";
    status(res.complete ? "" : "the chain stopped early: no next contact");
    await showChain(res.angles, res.joints, res.grasp);
  } catch (err) {
    if (mine !== wrapSeq) return;
    message(`cannot wrap: ${err.message}`);
    status("");
  }
}

$("rewrap").addEventListener("click", () => run(wrapChain));
for (const id of ["links", "sizeby", "laps", "linklen", "mode", "offset", "noise"]) {
  $(id).addEventListener("change", () => run(wrapChain));
}

$("copy").addEventListener("click", async () => {
  $("angles").select();
  try {
    await navigator.clipboard.writeText($("angles").value);
    status("copied");
  } catch (e) {
    document.execCommand("copy");
  }
});

// -------------------------------------------------------------- PNG upload
$("png").addEventListener("change", (e) => {
  const file = e.target.files[0];
  e.target.value = "";
  if (file) run(() => recogniseImage(file));
});

async function recogniseImage(file) {
  stopAnimation();
  message("");
  status("reading image...");
  try {
    const res = await upload("/api/outline/image", file);
    state.stroke = [];
    state.chain = null;
    state.outline = res.outline;
    state.view = fitView(canvas, [res.outline], 90);
    state.source = { outline: res.outline };
  } catch (err) {
    failed(err, "cannot use this image");
    return;
  }
  await recognise();
}

// ----------------------------------------------------------- robot angles
async function recogniseAngles(text) {
  stopAnimation();
  message("");
  status("recognising angles...");
  try {
    const res = await post("/api/angles", { csv: text, link_length: Number($("csvlink").value) });
    window.tentaclass.last.angles = res;
    const c = res.chains[0];
    state.stroke = [];
    state.outline = null;
    state.view = fitView(canvas, [c.joints]);
    showAnswer(c);
    $("chainanswer").textContent =
      (res.chains.length > 1 ? `; chain 1 of ${res.chains.length}` : "") +
      (c.full_lap ? "" : "; no full lap: the answer is a guess");
    status("");
    await showChain(c.angles, c.joints, c.grasp);
  } catch (err) {
    failed(err, "cannot use these angles");
  }
}

$("csvgo").addEventListener("click", () => run(() => recogniseAngles($("csv").value)));
$("csvfile").addEventListener("change", async (e) => {
  const file = e.target.files[0];
  e.target.value = "";
  if (!file) return;
  if (file.size > 2 * 1024 * 1024) {
    message("cannot use this file: it is larger than 2 MB");
    return;
  }
  $("csv").value = await file.text();
  run(() => recogniseAngles($("csv").value));
});

// ------------------------------------------------------------------ teach
function showExamples() {
  const n = state.examples.length;
  $("teachcount").textContent = `${n} example${n === 1 ? "" : "s"}`;
}

$("teachadd").addEventListener("click", () => {
  if (!state.source || !state.source.stroke || state.source.stroke.length < 3) {
    message("draw an example on the canvas first");
    return;
  }
  state.examples.push(state.source.stroke);
  showExamples();
  message("");
});

$("teachgo").addEventListener("click", () => run(teach));

async function teach() {
  message("");
  try {
    await post("/api/teach", { name: $("teachname").value, strokes: state.examples });
    status(`learned "${$("teachname").value}"`);
    state.examples = [];
    $("teachname").value = "";
    showExamples();
    await listClasses();
  } catch (err) {
    message(`cannot teach: ${err.message}`);
  }
}

async function listClasses() {
  const res = await get("/api/classes");
  const ul = $("classes");
  ul.innerHTML = "";
  for (const c of res.classes) {
    const li = document.createElement("li");
    li.dataset.cls = c.name;
    li.textContent = c.builtin ? `${c.name} (built in)` : `${c.name} (taught, ${c.examples} examples)`;
    if (!c.builtin) {
      const b = document.createElement("button");
      b.type = "button";
      b.textContent = "remove";
      b.addEventListener("click", () =>
        run(async () => {
          try {
            await del(`/api/classes/${encodeURIComponent(c.name)}`);
            await listClasses();
          } catch (err) {
            message(`cannot remove: ${err.message}`);
          }
        }),
      );
      li.appendChild(b);
    }
    ul.appendChild(li);
  }
}

document.body.dataset.actions = "0";
document.body.dataset.idle = "1";
plotAngles($("angleplot"), []);
redraw();
listClasses()
  .catch((err) => message(`cannot reach the server: ${err.message}`))
  .finally(() => {
    canvas.dataset.ready = "1";
  });
