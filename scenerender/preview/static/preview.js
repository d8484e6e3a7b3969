// The preview page: asks the server for frames of the view the user chose (frame, mode,
// camera), one request at a time (the newest wish wins), and long-polls /state to hear of
// saves (a new generation), errors and the scene's timeline and camera path.
"use strict";

const $ = (id) => document.getElementById(id);
const view = { frame: 0, mode: "", camera: null };   // camera: null = the scene's own
const known = { version: -1, generation: -1, scene: null, path: null, errors: [], shownCamera: null };
let inFlight = null;   // the promise of the frame request under way
let wanted = false;    // the view changed while a request was under way
let playing = false;

// -- frames

function viewQuery() {
  const params = new URLSearchParams({ frame: String(view.frame) });
  if (view.mode) params.set("mode", view.mode);
  if (view.camera) {
    const c = view.camera;
    params.set("camera", [...c.position, ...c.target, c.fov].map((v) => +v.toFixed(5)).join(","));
  }
  return params.toString();
}

function requestFrame() {
  if (inFlight) { wanted = true; return inFlight; }
  inFlight = fetchFrame().finally(() => {
    inFlight = null;
    if (wanted) { wanted = false; requestFrame(); }
  });
  return inFlight;
}

async function fetchFrame() {
  const asked = viewQuery();
  let response;
  try {
    response = await fetch(`/frame?${asked}`, { cache: "no-store" });
  } catch (error) {
    setStatus("server unreachable", true);
    return;
  }
  if (response.status === 409) return;           // a newer request took its place
  if (!response.ok) {
    const body = await response.json().catch(() => ({ errors: [`HTTP ${response.status}`] }));
    showErrors(body.errors || []);
    return;
  }
  const camera = JSON.parse(response.headers.get("X-Camera"));
  const generation = Number(response.headers.get("X-Generation"));
  const seconds = Number(response.headers.get("X-Render-Seconds"));
  const blob = await response.blob();
  await showImage(blob);
  known.shownCamera = camera;
  $("camera-yaml").textContent = camera.yaml;
  showErrors([]);
  setStatus(`frame ${response.headers.get("X-Frame")} · rendered in ${(seconds * 1000).toFixed(0)} ms`);
  window.previewShown = { generation, frame: Number(response.headers.get("X-Frame")), at: Date.now(),
                          renderSeconds: seconds, query: asked };
  drawPath();
  if (known.scene && known.scene.check && !playing) checkFrame(view.frame);
}

function shownWidth(natural) {
  // beside a reference both are as wide, to compare; alone, a small frame is enlarged to be seen
  if (known.scene && known.scene.check) return 420;
  return natural <= 426 ? 640 : natural;
}

function showImage(blob) {
  const img = $("frame");
  const url = URL.createObjectURL(blob);
  return new Promise((resolve) => {
    img.onload = () => {
      if (img.dataset.url) URL.revokeObjectURL(img.dataset.url);
      img.dataset.url = url;
      img.style.width = `${shownWidth(img.naturalWidth)}px`;
      resolve();
    };
    img.onerror = () => resolve();
    img.src = url;
  });
}

// -- state: saves, errors, the scene's facts

async function poll() {
  for (;;) {
    try {
      const response = await fetch(`/state?since=${known.version}`, { cache: "no-store" });
      applyState(await response.json());
    } catch (error) {
      setStatus("server unreachable", true);
      await new Promise((resolve) => setTimeout(resolve, 1000));
    }
  }
}

function applyState(state) {
  known.version = state.version;
  if (state.scene) applyScene(state.scene);
  known.path = state.path;
  document.body.dataset.renders = String(state.renders);
  showErrors(state.errors);
  if (state.generation !== known.generation) {
    known.generation = state.generation;
    requestFrame();
  }
  drawPath();
}

function applyScene(scene) {
  const first = known.scene === null;
  known.scene = scene;
  const [w, h] = scene.size;
  const [pw, ph] = scene.preview_size;
  $("scene-name").textContent = scene.name;
  $("scene-name").title = `${w}x${h}; previewed at ${pw}x${ph}`;
  $("scene-size").textContent = pw === w && ph === h ? `${w}x${h}` : `${pw}x${ph} of ${w}x${h}`;
  const timeline = $("timeline");
  timeline.max = String(Math.max(0, scene.frame_count - 1));
  if (view.frame > scene.frame_count - 1) view.frame = Math.max(0, scene.frame_count - 1);
  timeline.value = String(view.frame);
  const select = $("mode");
  select.options[0].textContent = `the scene's (${scene.mode})`;
  if (first) {
    for (const mode of scene.modes) select.add(new Option(mode, mode));
    $("check").hidden = !scene.check;
    if (scene.check) checkFrame(view.frame);
    const img = $("frame");  // a frame shown before the scene's facts came: its width again
    if (img.naturalWidth) img.style.width = `${shownWidth(img.naturalWidth)}px`;
  }
  showFrameLabel();
}

function showErrors(lines) {
  known.errors = lines;
  const list = $("errors");
  list.replaceChildren(...lines.map(errorItem));
  list.hidden = lines.length === 0;
  if (lines.length) setStatus(`${lines.length} problem${lines.length > 1 ? "s" : ""}: showing the last good frame`, true);
}

function errorItem(line) {
  // "scene.yaml:12:5: objects[0].mesh: message": the place stands out
  const item = document.createElement("li");
  const match = line.match(/^(.*?:\d+(?::\d+)?): (.*)$/);
  if (match) {
    const where = document.createElement("span");
    where.className = "where";
    where.textContent = match[1];
    item.append(where, `: ${match[2]}`);
  } else {
    item.textContent = line;
  }
  return item;
}

function setStatus(text, bad = false) {
  const status = $("status");
  status.textContent = text;
  status.classList.toggle("bad", bad);
}

// -- time

function showFrameLabel() {
  const scene = known.scene;
  const fps = scene ? scene.fps : 1;
  const count = scene ? scene.frame_count : 1;
  $("frame-label").textContent = `frame ${view.frame} / ${count - 1} · ${(view.frame / fps).toFixed(3)} s`;
}

function goToFrame(index) {
  view.frame = index;
  $("timeline").value = String(index);
  showFrameLabel();
  return requestFrame();
}

async function play() {
  playing = !playing;
  $("play").textContent = playing ? "❚❚" : "▶";
  while (playing && known.scene) {
    const started = performance.now();
    await goToFrame((view.frame + 1) % known.scene.frame_count);
    const wait = 1000 / known.scene.fps - (performance.now() - started);
    if (wait > 0) await new Promise((resolve) => setTimeout(resolve, wait));
  }
  if (known.scene && known.scene.check) checkFrame(view.frame);
}

// -- camera: orbit, dolly, fly

const sub = (a, b) => a.map((v, i) => v - b[i]);
const add = (a, b) => a.map((v, i) => v + b[i]);
const scale = (a, s) => a.map((v) => v * s);
const length = (a) => Math.hypot(...a);
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const unit = (a) => scale(a, 1 / (length(a) || 1));

function currentCamera() {
  const c = view.camera || known.shownCamera;
  if (!c) return null;
  return { position: [...c.position], target: [...c.target], fov: c.fov || 60 };
}

function orbit(start, dx, dy) {
  const offset = sub(start.position, start.target);
  const radius = length(offset) || 1;
  let azimuth = Math.atan2(offset[0], offset[2]) - dx * 0.01;
  let elevation = Math.asin(Math.max(-1, Math.min(1, offset[1] / radius))) + dy * 0.01;
  elevation = Math.max(-1.55, Math.min(1.55, elevation));
  const position = add(start.target, [radius * Math.cos(elevation) * Math.sin(azimuth), radius * Math.sin(elevation),
                                      radius * Math.cos(elevation) * Math.cos(azimuth)]);
  return { ...start, position };
}

function dolly(start, steps) {
  const offset = sub(start.position, start.target);
  const factor = Math.exp(steps * 0.1);
  const radius = Math.max(0.01, length(offset) * factor);
  return { ...start, position: add(start.target, scale(unit(offset), radius)) };
}

function fly(start, key) {
  const forward = unit(sub(start.target, start.position));
  const right = unit(cross(forward, [0, 1, 0]));
  const step = Math.max(0.05, length(sub(start.target, start.position)) * 0.08);
  const moves = { w: forward, s: scale(forward, -1), d: right, a: scale(right, -1), e: [0, 1, 0], q: [0, -1, 0] };
  const move = scale(moves[key], step);
  return { ...start, position: add(start.position, move), target: add(start.target, move) };
}

function placeCamera(camera) {
  view.camera = camera;
  requestFrame();
}

function setUpCamera() {
  const stage = $("stage");
  let drag = null;
  stage.addEventListener("pointerdown", (event) => {
    const camera = currentCamera();
    if (!camera) return;
    drag = { x: event.clientX, y: event.clientY, camera };
    stage.setPointerCapture(event.pointerId);
    stage.focus();
    event.preventDefault();
  });
  stage.addEventListener("pointermove", (event) => {
    if (!drag) return;
    placeCamera(orbit(drag.camera, event.clientX - drag.x, event.clientY - drag.y));
  });
  const end = () => { drag = null; };
  stage.addEventListener("pointerup", end);
  stage.addEventListener("pointercancel", end);
  stage.addEventListener("wheel", (event) => {
    const camera = currentCamera();
    if (!camera) return;
    event.preventDefault();
    placeCamera(dolly(camera, Math.sign(event.deltaY)));
  }, { passive: false });
  document.addEventListener("keydown", (event) => {
    if (event.target instanceof HTMLInputElement || event.target instanceof HTMLSelectElement) return;
    const key = event.key.toLowerCase();
    if (key === " ") { event.preventDefault(); play(); return; }
    if (!"wasdqe".includes(key) || key.length !== 1 || event.ctrlKey || event.metaKey) return;
    const camera = currentCamera();
    if (camera) placeCamera(fly(camera, key));
  });
  $("reset-camera").addEventListener("click", () => { view.camera = null; requestFrame(); });
  $("copy-camera").addEventListener("click", () => navigator.clipboard.writeText($("camera-yaml").textContent));
}

// -- the camera path, seen from above (x to the right, z down the page)

function drawPath() {
  const svg = $("path");
  const path = known.path;
  $("path-box").hidden = !path;  // an <svg> has no hidden attribute of its own
  if (!path) return;
  const here = currentCamera();
  const all = [...path.points, ...path.keys, ...(here ? [here.position] : [])];
  const xs = all.map((p) => p[0]);
  const zs = all.map((p) => p[2]);
  const span = Math.max(Math.max(...xs) - Math.min(...xs), Math.max(...zs) - Math.min(...zs), 1e-3);
  const pad = span * 0.1;
  const [x0, z0, size] = [Math.min(...xs) - pad, Math.min(...zs) - pad, span + 2 * pad];
  svg.setAttribute("viewBox", `${x0} ${z0} ${size} ${size}`);
  const r = size * 0.015;
  const line = path.points.map((p) => `${p[0]},${p[2]}`).join(" ");
  const keys = path.keys.map((p) => `<circle class="key" cx="${p[0]}" cy="${p[2]}" r="${r}" fill="#ffd479"/>`).join("");
  const marker = pathPointAt(path, view.frame);
  const current = marker ? `<circle id="path-current" cx="${marker[0]}" cy="${marker[2]}" r="${r * 1.6}" fill="none"`
      + ` stroke="#ff5f56" stroke-width="${r * 0.6}"/>` : "";
  const placed = view.camera ? `<rect x="${here.position[0] - r}" y="${here.position[2] - r}" width="${2 * r}"`
      + ` height="${2 * r}" fill="#7ee787"/>` : "";
  svg.innerHTML = `<polyline points="${line}" fill="none" stroke="#4a90d9" stroke-width="${r * 0.5}"/>`
      + keys + current + placed;
}

function pathPointAt(path, frame) {
  let best = 0;
  path.frames.forEach((f, i) => { if (Math.abs(f - frame) < Math.abs(path.frames[best] - frame)) best = i; });
  return path.points[best];
}

// -- the reference check (--check REF/)

let checking = 0;
async function checkFrame(frame) {
  const ticket = ++checking;
  const verdict = $("verdict");
  verdict.textContent = "checking…";
  verdict.className = "verdict";
  const reference = $("reference");
  reference.onload = () => { reference.style.width = `${shownWidth(reference.naturalWidth)}px`; };
  reference.src = `/reference?frame=${frame}&generation=${known.generation}`;
  const response = await fetch(`/check?frame=${frame}`, { cache: "no-store" });
  if (response.status === 409 || ticket !== checking) return;
  const body = await response.json();
  if (body.errors) { verdict.textContent = body.errors.join("; "); verdict.className = "verdict fail"; return; }
  verdict.textContent = body.line;
  verdict.className = body.reference ? `verdict ${body.passed ? "pass" : "fail"}` : "verdict";
}

// -- start

$("timeline").addEventListener("input", (event) => goToFrame(Number(event.target.value)));
$("play").addEventListener("click", play);
$("mode").addEventListener("change", (event) => { view.mode = event.target.value; requestFrame(); });
setUpCamera();
poll();
