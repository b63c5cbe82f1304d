// kinetree view: the page. It draws what the server computes (or what --export embedded) and
// never computes kinematics itself. Uses the global THREE (three.min.js).
(function () {
  'use strict';
  const EMBED = window.KINETREE_EMBED || null;
  const $ = (id) => document.getElementById(id);
  // Shown when a model has no visual geometry and its collision geometry stands in.
  const FALLBACK_COLOR = 0x3f7fbf;
  const DEFAULT_COLOR = 0xa8a8a8;
  const COLLIDING_COLOR = 0xe02020;
  const COLLISION_COLOR = 0xe0a030;

  const state = {
    model: null, q: [], poses: null, linkGroups: [], frameAxes: [], labels: [],
    collisionMeshes: [], // per link: [THREE.Mesh]
    collisionMaterials: [], // per link: material
    standIn: [], // per link: collision geometry shown for missing visuals
    fallback: false, busy: false, pending: false, ready: false, trajectory: null,
  };
  window.kinetree = state;

  function setStatus(text, error) {
    const s = $('status');
    s.textContent = text;
    s.className = error ? 'error' : '';
  }

  async function api(path, body) {
    const init = body === undefined ? {} : {
      method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify(body),
    };
    const r = await fetch(path, init);
    const j = await r.json();
    if (!r.ok) throw new Error(j.error || ('HTTP ' + r.status));
    return j;
  }

  function b64bytes(s) {
    const bin = atob(s);
    const out = new Uint8Array(bin.length);
    for (let i = 0; i < bin.length; i++) out[i] = bin.charCodeAt(i);
    return out;
  }

  async function fileBytes(url) {
    if (EMBED) {
      const s = EMBED.meshes[url];
      if (s === undefined) throw new Error('mesh not embedded: ' + url);
      return b64bytes(s).buffer;
    }
    const r = await fetch(url);
    if (!r.ok) throw new Error(url + ': HTTP ' + r.status);
    return r.arrayBuffer();
  }

  // ---- scene ----
  const container = $('view');
  const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  container.appendChild(renderer.domElement);
  const labelRenderer = new THREE.CSS2DRenderer();
  labelRenderer.domElement.style.position = 'absolute';
  labelRenderer.domElement.style.top = '0';
  labelRenderer.domElement.style.pointerEvents = 'none';
  container.appendChild(labelRenderer.domElement);
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(0xeef0f2);
  const camera = new THREE.PerspectiveCamera(45, 1, 0.01, 100);
  camera.up.set(0, 0, 1);
  camera.position.set(1.6, 1.2, 1.1);
  scene.add(new THREE.HemisphereLight(0xffffff, 0x808080, 1.6));
  const sun = new THREE.DirectionalLight(0xffffff, 1.6);
  sun.position.set(2, 1, 3);
  scene.add(sun);
  const grid = new THREE.GridHelper(2, 20, 0x999999, 0xcccccc);
  grid.rotation.x = Math.PI / 2;
  scene.add(grid);
  const orbit = new THREE.OrbitControls(camera, renderer.domElement);
  orbit.target.set(0, 0, 0.4);
  orbit.update();
  const comMarker = new THREE.Mesh(new THREE.SphereGeometry(0.025, 16, 12),
    new THREE.MeshStandardMaterial({ color: 0xd000d0 }));
  comMarker.visible = false;
  scene.add(comMarker);

  function resize() {
    const w = container.clientWidth, h = container.clientHeight;
    renderer.setSize(w, h);
    labelRenderer.setSize(w, h);
    camera.aspect = w / Math.max(h, 1);
    camera.updateProjectionMatrix();
  }
  window.addEventListener('resize', resize);
  resize();

  function render() {
    renderer.render(scene, camera);
    labelRenderer.render(scene, camera);
  }
  orbit.addEventListener('change', render);

  // ---- geometry ----
  function primitive(g) {
    switch (g.type) {
      case 'box': return new THREE.BoxGeometry(g.size[0], g.size[1], g.size[2]);
      case 'sphere': return new THREE.SphereGeometry(g.radius, 32, 16);
      case 'cylinder': return new THREE.CylinderGeometry(g.radius, g.radius, g.length, 32).rotateX(Math.PI / 2);
      case 'capsule': return new THREE.CapsuleGeometry(g.radius, g.length, 8, 24).rotateX(Math.PI / 2);
      default: return null;
    }
  }

  function withMaterial(object, material) {
    object.traverse((o) => { if (o.isMesh) o.material = material; });
    return object;
  }

  async function meshObject(g, material, keepMaterials) {
    if (!g.url) throw new Error('mesh not found: ' + g.filename);
    const ext = g.filename.split('.').pop().toLowerCase();
    const bytes = await fileBytes(g.url);
    let object;
    if (ext === 'stl') {
      object = new THREE.Mesh(new THREE.STLLoader().parse(bytes), material);
    } else if (ext === 'obj') {
      object = withMaterial(new THREE.OBJLoader().parse(new TextDecoder().decode(bytes)), material);
    } else if (ext === 'dae') {
      const base = g.url.substring(0, g.url.lastIndexOf('/') + 1);
      const collada = new THREE.ColladaLoader().parse(new TextDecoder().decode(bytes), base);
      object = collada.scene;
      // URDF mesh files are read in their own axes (as ROS tools do): undo the loader's
      // Z-up to Y-up turn and keep its unit scale.
      object.rotation.set(0, 0, 0);
      if (!keepMaterials) withMaterial(object, material);
    } else {
      throw new Error('unsupported mesh format: ' + g.filename);
    }
    object.scale.multiply(new THREE.Vector3(g.scale[0], g.scale[1], g.scale[2]));
    return object;
  }

  async function element(e, material, keepMaterials) {
    const geometry = primitive(e.geometry);
    const object = geometry ? new THREE.Mesh(geometry, material)
      : await meshObject(e.geometry, material, keepMaterials);
    const o = e.origin;
    object.position.set(o[0], o[1], o[2]);
    object.quaternion.set(o[3], o[4], o[5], o[6]);
    return object;
  }

  async function buildRobot(model) {
    const problems = [];
    for (let i = 0; i < model.links.length; i++) {
      const link = model.links[i];
      const group = new THREE.Group();
      group.name = link.name;
      const visual = new THREE.Group();
      visual.name = 'visual';
      const collision = new THREE.Group();
      collision.name = 'collision';
      group.add(visual, collision);
      for (const v of link.visuals) {
        const c = v.color;
        const material = new THREE.MeshStandardMaterial({
          color: c ? new THREE.Color(c[0], c[1], c[2]) : DEFAULT_COLOR,
          transparent: !!c && c[3] < 1, opacity: c ? c[3] : 1, metalness: 0.1, roughness: 0.6,
        });
        try { visual.add(await element(v, material, !c)); } catch (err) { problems.push(err.message); }
      }
      // A link whose visual geometry is missing (none, or its mesh files are not found) shows
      // its collision geometry in its place.
      const standIn = visual.children.length === 0;
      const cmaterial = standIn
        ? new THREE.MeshStandardMaterial({ color: FALLBACK_COLOR, metalness: 0.1, roughness: 0.6 })
        : new THREE.MeshStandardMaterial({ color: COLLISION_COLOR, transparent: true, opacity: 0.45 });
      state.collisionMaterials.push(cmaterial);
      state.standIn.push(standIn);
      for (const c of link.collisions) {
        try { collision.add(await element(c, cmaterial, false)); } catch (err) { problems.push(err.message); }
      }
      const axes = new THREE.AxesHelper(0.1);
      axes.visible = false;
      group.add(axes);
      state.frameAxes.push(axes);
      const div = document.createElement('div');
      div.className = 'label';
      div.textContent = link.name;
      const label = new THREE.CSS2DObject(div);
      label.visible = false;
      group.add(label);
      state.labels.push(label);
      scene.add(group);
      state.linkGroups.push(group);
    }
    state.fallback = state.standIn.some((x) => x);
    applyVisibility();
    return problems;
  }

  function applyVisibility() {
    const showVisual = $('show-visual').checked, showCollision = $('show-collision').checked;
    state.linkGroups.forEach((g, i) => {
      g.getObjectByName('visual').visible = showVisual;
      g.getObjectByName('collision').visible = showCollision || (showVisual && state.standIn[i]);
    });
    for (const a of state.frameAxes) a.visible = $('show-frames').checked;
    for (const l of state.labels) { l.visible = $('show-names').checked; l.element.style.display = l.visible ? '' : 'none'; }
    comMarker.visible = $('show-com').checked;
    if (workspacePoints) workspacePoints.visible = $('show-workspace').checked;
    render();
  }

  // ---- poses ----
  function applyLinkPoses(links) {
    for (let i = 0; i < links.length && i < state.linkGroups.length; i++) {
      const p = links[i];
      state.linkGroups[i].position.set(p[0], p[1], p[2]);
      state.linkGroups[i].quaternion.set(p[3], p[4], p[5], p[6]);
    }
  }

  function applyPoses(poses) {
    state.poses = poses;
    applyLinkPoses(poses.links);
    comMarker.position.set(poses.com[0], poses.com[1], poses.com[2]);
    placeGizmo();
    render();
  }

  function applyCollisions(answer) {
    const red = new Set();
    for (const p of answer.pairs || []) {
      if (p.colliding) { red.add(p.link_a); red.add(p.link_b); }
    }
    const model = state.model;
    for (let i = 0; i < model.links.length; i++) {
      const m = state.collisionMaterials[i];
      const base = state.standIn[i] ? FALLBACK_COLOR : COLLISION_COLOR;
      m.color.setHex(red.has(model.links[i].name) ? COLLIDING_COLOR : base);
    }
    const n = red.size ? [...red].join(', ') : 'none';
    $('status').dataset.colliding = n;
    render();
  }

  // One request in flight; the latest configuration wins.
  async function update() {
    if (EMBED) return;
    if (state.busy) { state.pending = true; return; }
    state.busy = true;
    try {
      do {
        state.pending = false;
        const q = state.q.slice();
        applyPoses(await api('/api/fk', { q }));
        applyCollisions(await api('/api/collide', { q }));
        setStatus('colliding links: ' + $('status').dataset.colliding);
      } while (state.pending);
    } catch (err) {
      setStatus(err.message, true);
    } finally {
      state.busy = false;
      state.ready = true;
    }
  }

  // ---- sliders ----
  const sliders = []; // {index, range, number}

  function jointRange(j, k) {
    if (j.kind === 'continuous') return [-Math.PI, Math.PI];
    if (j.kind === 'floating') return k < 3 ? [-2, 2] : [-Math.PI, Math.PI];
    if (isFinite(j.lower) && isFinite(j.upper) && j.upper > j.lower) return [j.lower, j.upper];
    return j.kind === 'prismatic' ? [-1, 1] : [-Math.PI, Math.PI];
  }

  // A floating base is shown as x, y, z, roll, pitch, yaw and sent as x, y, z and a quaternion.
  const floatingRpy = {};

  function syncFloating(j) {
    const v = floatingRpy[j.name];
    const quat = new THREE.Quaternion().setFromEuler(new THREE.Euler(v[3], v[4], v[5], 'ZYX'));
    const i = j.q_index;
    state.q[i] = v[0]; state.q[i + 1] = v[1]; state.q[i + 2] = v[2];
    state.q[i + 3] = quat.x; state.q[i + 4] = quat.y; state.q[i + 5] = quat.z; state.q[i + 6] = quat.w;
  }

  function floatingFromQ(j) {
    const i = j.q_index;
    const e = new THREE.Euler().setFromQuaternion(
      new THREE.Quaternion(state.q[i + 3], state.q[i + 4], state.q[i + 5], state.q[i + 6]), 'ZYX');
    floatingRpy[j.name] = [state.q[i], state.q[i + 1], state.q[i + 2], e.x, e.y, e.z];
  }

  function buildSliders(model) {
    const box = $('joints');
    for (const j of model.joints) {
      if (j.mimic) continue;
      let names;
      if (j.kind === 'floating') { names = ['x', 'y', 'z', 'roll', 'pitch', 'yaw']; floatingFromQ(j); }
      else if (j.nq === 1) names = [''];
      else continue; // spherical/planar/cylindrical: not editable here
      names.forEach((suffix, k) => {
        const [lo, hi] = jointRange(j, k);
        const div = document.createElement('div');
        div.className = 'joint';
        const label = document.createElement('label');
        label.textContent = j.name + (suffix ? ' ' + suffix : '') + (j.kind === 'prismatic' || (j.kind === 'floating' && k < 3) ? ' (m)' : ' (rad)');
        const range = document.createElement('input');
        range.type = 'range'; range.min = lo; range.max = hi; range.step = (hi - lo) / 1000;
        range.dataset.joint = j.name + (suffix ? ':' + suffix : '');
        const number = document.createElement('input');
        number.type = 'number'; number.step = 'any';
        const get = () => (j.kind === 'floating' ? floatingRpy[j.name][k] : state.q[j.q_index]);
        const set = (x) => {
          if (!isFinite(x)) return;
          if (j.kind === 'floating') { floatingRpy[j.name][k] = x; syncFloating(j); }
          else state.q[j.q_index] = x;
          show();
          update();
        };
        const show = () => { range.value = get(); number.value = (+get()).toFixed(4); };
        range.addEventListener('input', () => set(parseFloat(range.value)));
        number.addEventListener('change', () => set(parseFloat(number.value)));
        div.append(label, range, number);
        box.appendChild(div);
        sliders.push({ show, range, number, joint: j, k, lo, hi });
        show();
      });
    }
    if (EMBED) for (const s of sliders) { s.range.disabled = true; s.number.disabled = true; }
  }

  function showAll() {
    for (const j of state.model.joints) if (j.kind === 'floating') floatingFromQ(j);
    for (const s of sliders) s.show();
  }

  $('neutral').addEventListener('click', () => {
    for (const j of state.model.joints) j.neutral.forEach((x, k) => { state.q[j.q_index + k] = x; });
    showAll();
    update();
  });
  $('random').addEventListener('click', () => {
    for (const s of sliders) {
      const x = s.lo + Math.random() * (s.hi - s.lo);
      if (s.joint.kind === 'floating') floatingRpy[s.joint.name][s.k] = x; else state.q[s.joint.q_index] = x;
    }
    for (const j of state.model.joints) if (j.kind === 'floating') syncFloating(j);
    showAll();
    update();
  });
  for (const id of ['show-visual', 'show-collision', 'show-frames', 'show-names', 'show-com', 'show-workspace']) {
    $(id).addEventListener('change', applyVisibility);
  }

  // ---- IK gizmo ----
  const gizmoTarget = new THREE.Object3D();
  scene.add(gizmoTarget);
  const gizmo = new THREE.TransformControls(camera, renderer.domElement);
  gizmo.setSize(0.8);
  const gizmoHelper = gizmo.getHelper();
  scene.add(gizmoHelper);
  gizmo.attach(gizmoTarget);
  gizmo.enabled = false;
  gizmoHelper.visible = false;
  let dragging = false;
  gizmo.addEventListener('dragging-changed', (e) => { orbit.enabled = !e.value; dragging = e.value; });
  gizmo.addEventListener('change', render);

  function ikFrameIndex() {
    const name = $('ik-frame').value;
    const model = state.model;
    const f = model.frames.indexOf(name);
    if (f >= 0) return ['frames', f];
    return ['links', model.links.findIndex((l) => l.name === name)];
  }

  function placeGizmo() {
    if (dragging || !state.poses) return;
    const [kind, i] = ikFrameIndex();
    const p = i >= 0 ? state.poses[kind][i] : null;
    if (!p) return;
    gizmoTarget.position.set(p[0], p[1], p[2]);
    gizmoTarget.quaternion.set(p[3], p[4], p[5], p[6]);
  }

  let ikBusy = false, ikPending = false;
  async function solveIk() {
    if (ikBusy) { ikPending = true; return; }
    ikBusy = true;
    try {
      do {
        ikPending = false;
        const t = gizmoTarget;
        const target = { xyz: [t.position.x, t.position.y, t.position.z] };
        if (!$('ik-position').checked) target.quat = [t.quaternion.x, t.quaternion.y, t.quaternion.z, t.quaternion.w];
        const answer = await api('/api/ik', { q: state.q, frame: $('ik-frame').value, target });
        state.q = answer.q.slice();
        showAll();
        applyPoses(answer);
        applyCollisions(await api('/api/collide', { q: state.q }));
        setStatus('IK ' + answer.status + ': position error ' + answer.position_error.toExponential(2) +
          ' m, orientation error ' + answer.orientation_error.toExponential(2) + ' rad, ' +
          answer.iterations + ' iterations');
      } while (ikPending);
    } catch (err) {
      setStatus(err.message, true);
    } finally {
      ikBusy = false;
    }
  }
  gizmo.addEventListener('objectChange', solveIk);
  $('ik-on').addEventListener('change', () => {
    gizmo.enabled = $('ik-on').checked;
    gizmoHelper.visible = gizmo.enabled;
    placeGizmo();
    render();
  });
  $('ik-frame').addEventListener('change', () => { placeGizmo(); render(); });
  window.addEventListener('keydown', (e) => {
    if (e.key === 'r') gizmo.setMode('rotate');
    if (e.key === 't') gizmo.setMode('translate');
  });

  // ---- workspace ----
  let workspacePoints = null;
  function showWorkspace(bytes) {
    const loader = new THREE.PLYLoader();
    loader.setCustomPropertyNameMapping({ manipulability: ['manipulability'] });
    const geometry = loader.parse(bytes);
    const m = geometry.getAttribute('manipulability');
    const n = geometry.getAttribute('position').count;
    const colors = new Float32Array(3 * n);
    let lo = Infinity, hi = -Infinity;
    if (m) for (let i = 0; i < n; i++) { lo = Math.min(lo, m.getX(i)); hi = Math.max(hi, m.getX(i)); }
    const c = new THREE.Color();
    for (let i = 0; i < n; i++) {
      const s = m && hi > lo ? (m.getX(i) - lo) / (hi - lo) : 0.5;
      c.setHSL(0.7 * (1 - s), 0.9, 0.5); // blue (low) to red (high manipulability)
      colors.set([c.r, c.g, c.b], 3 * i);
    }
    geometry.setAttribute('color', new THREE.BufferAttribute(colors, 3));
    workspacePoints = new THREE.Points(geometry, new THREE.PointsMaterial({ size: 0.01, vertexColors: true }));
    scene.add(workspacePoints);
    $('show-workspace-label').hidden = false;
  }

  // ---- trajectory ----
  let playing = false, playStart = 0, playFrom = 0;
  function showSample(k) {
    const tr = state.trajectory;
    k = Math.max(0, Math.min(tr.t.length - 1, k));
    $('time-slider').value = k;
    $('time').textContent = tr.t[k].toFixed(3) + ' s';
    state.q = tr.q[k].slice();
    showAll();
    applyLinkPoses(tr.links[k]);
    render();
  }
  function tick(now) {
    if (!playing) return;
    const tr = state.trajectory;
    const t = playFrom + (now - playStart) / 1000;
    let k = tr.t.findIndex((x) => x >= t);
    if (k < 0) { k = tr.t.length - 1; playing = false; $('play').textContent = 'Play'; }
    showSample(k);
    if (playing) requestAnimationFrame(tick);
  }
  function setupTrajectory(tr) {
    state.trajectory = tr;
    $('trajectory-box').hidden = false;
    $('time-slider').max = tr.t.length - 1;
    $('time-slider').addEventListener('input', () => { playing = false; $('play').textContent = 'Play'; showSample(+$('time-slider').value); });
    $('play').addEventListener('click', () => {
      playing = !playing;
      $('play').textContent = playing ? 'Pause' : 'Play';
      if (playing) {
        let k = +$('time-slider').value;
        if (k >= tr.t.length - 1) k = 0;
        playFrom = tr.t[k];
        playStart = performance.now();
        requestAnimationFrame(tick);
      }
    });
  }

  // ---- start ----
  /** Screen position (CSS pixels, page coordinates) of a link's origin: for tests. */
  window.kinetreeProject = function (name) {
    const i = state.model.links.findIndex((l) => l.name === name);
    const v = state.linkGroups[i].getWorldPosition(new THREE.Vector3()).project(camera);
    const r = renderer.domElement.getBoundingClientRect();
    return [r.left + (v.x + 1) / 2 * r.width, r.top + (1 - v.y) / 2 * r.height];
  };

  async function start() {
    try {
      const model = EMBED ? EMBED.model : await api('/api/model');
      state.model = model;
      state.q = model.initial_q.slice();
      $('title').textContent = model.name;
      document.title = model.name + ' — kinetree view';
      // IK targets: links and frames, not a composite joint's internal (virtual) links.
      const names = model.links.filter((l) => !l.virtual).map((l) => l.name).concat(model.frames);
      for (const name of names) {
        const o = document.createElement('option');
        o.textContent = name;
        $('ik-frame').appendChild(o);
      }
      // A hand, tool or end-effector link if there is one, else the last link.
      $('ik-frame').value = names.find((n) => /hand|tool|ee|tcp|gripper/i.test(n)) || names[names.length - 1];
      if (EMBED) for (const id of ['ik-box', 'neutral', 'random']) $(id).hidden = true;
      const problems = await buildRobot(model);
      buildSliders(model);
      const tr = EMBED ? EMBED.trajectory : await api('/api/trajectory');
      if (tr) setupTrajectory(tr);
      if (EMBED) {
        if (EMBED.workspace) showWorkspace(b64bytes(EMBED.workspace).buffer);
        applyPoses(EMBED.poses);
        applyCollisions(EMBED.collide);
        state.ready = true;
        setStatus('exported view (read-only)' + (problems.length ? '\n' + problems.length +
          ' visual mesh(es) not found: collision geometry shown instead (blue)' : ''));
      } else {
        const ws = await fetch('/api/workspace');
        if (ws.ok) showWorkspace(await ws.arrayBuffer());
        await update();
        if (problems.length) {
          setStatus($('status').textContent + '\n' + problems.length +
            ' visual mesh(es) not found: collision geometry shown instead (blue)');
        }
      }
      // Tests wait for this attribute.
      document.body.dataset.ready = 'true';
    } catch (err) {
      setStatus(err.message, true);
      document.body.dataset.ready = 'error';
    }
  }
  start();
})();
