// taskmap view MAP.h5: palms as glyphs coloured by cluster, the selected grasp's hand posed on
// the object with its contacts, filters, a list, ghosts. Everything is in the object frame.
// Side panel: title, filters (cluster, epsilon, hold), ghosts, legend, list.
TM.mapUi = function (side, D, state, filtered, refresh, select, reps, clusterOf) {
  const G = D.grasps;
  side.appendChild(TM.el('h1', {}, D.object.name + ' \u00d7 ' + D.hand_name));
  side.appendChild(TM.el('div', { class: 'tm-note' }, (D.source ? D.source + ': ' : '') + G.n + ' grasps, ' +
    D.clusters.length + ' clusters' + (D.hand ? '' : ' (hand model not found: palms only)')));
  const cl = TM.el('select', { id: 'tm-cluster' });
  cl.appendChild(TM.el('option', { value: 'all' }, 'all clusters'));
  D.clusters.forEach((c) => cl.appendChild(TM.el('option', { value: String(c.id) },
    'cluster ' + c.id + ' (' + c.size + ', best \u03b5 ' + TM.fmt(c.best_eps, 3) + ')')));
  if (D.clusters.length) cl.appendChild(TM.el('option', { value: '-1' }, 'outliers'));
  cl.onchange = () => { state.cluster = cl.value; refresh(); };
  const lab = TM.el('label', {}, 'cluster ');
  lab.appendChild(cl);
  side.appendChild(lab);
  const maxEps = G.eps.reduce((a, b) => Math.max(a, b), 1e-9);
  const eps = TM.el('input', { type: 'range', id: 'tm-eps', min: '0', max: String(maxEps), step: String(maxEps / 200), value: '0' });
  const epsLab = TM.el('label', {}, '\u03b5 \u2265 0');
  eps.oninput = () => { state.eps = Number(eps.value); epsLab.firstChild.textContent = '\u03b5 \u2265 ' + TM.fmt(state.eps, 4); refresh(); };
  epsLab.appendChild(eps);
  side.appendChild(epsLab);
  if (D.hold) {
    const hs = TM.el('select', { id: 'tm-hold' });
    hs.appendChild(TM.el('option', { value: 'all' }, 'all holds'));
    [...new Set(D.hold.labels)].sort().forEach((h) => hs.appendChild(TM.el('option', { value: h }, h)));
    hs.onchange = () => { state.hold = hs.value; refresh(); };
    const hl = TM.el('label', {}, 'hold ');
    hl.appendChild(hs);
    side.appendChild(hl);
  }
  const gh = TM.el('input', { type: 'checkbox', id: 'tm-ghosts' });
  gh.checked = state.ghosts;
  gh.onchange = () => { state.ghosts = gh.checked; refresh(); };
  const gl = TM.el('label');
  gl.appendChild(gh);
  gl.appendChild(document.createTextNode(' filtered grasps as ghost hands (best ' + D.ghost_limit + ')'));
  side.appendChild(gl);
  const legend = TM.el('div', { class: 'tm-note' });
  D.clusters.slice(0, TM.palette.length).forEach((c) => {
    legend.appendChild(TM.el('span', { class: 'tm-swatch', style: 'background:' + TM.clusterColor(c.id) }));
    legend.appendChild(document.createTextNode(c.id + ' '));
  });
  legend.appendChild(document.createTextNode('\u25cf black: representative; yellowish link: touches the object'));
  side.appendChild(legend);
  side.appendChild(TM.el('h2', {}, 'grasps (best \u03b5 first)'));
  side.appendChild(TM.el('div', { class: 'tm-list' }));
};
// The list of filtered grasps, best epsilon first (at most 400 rows).
TM.fillList = function (list, idx, G, reps, clusterOf, select, selected) {
  list.textContent = '';
  const sorted = idx.slice().sort((a, b) => G.eps[b] - G.eps[a]);
  sorted.slice(0, 400).forEach((i) => {
    const c = clusterOf(i);
    const row = TM.el('div', { 'data-i': String(i) });
    row.appendChild(TM.el('span', { class: 'tm-swatch', style: 'background:' + TM.clusterColor(c) }));
    row.appendChild(document.createTextNode('#' + i + '  \u03b5 ' + TM.fmt(G.eps[i], 4) +
      (c === null ? '' : c < 0 ? '  outlier' : '  c' + c) + (reps.has(i) ? '  \u2605' : '')));
    if (i === selected) row.classList.add('sel');
    row.onclick = () => select(i);
    list.appendChild(row);
  });
  if (sorted.length > 400) list.appendChild(TM.el('div', { class: 'tm-note' }, '\u2026 ' + (sorted.length - 400) + ' more (filter to see them)'));
  return sorted;
};
// Contact rows of grasp i.
TM.contactsOf = (G, i) => {
  const out = [];
  for (let k = G.off[i]; k < G.off[i + 1]; ++k) out.push(k);
  return out;
};
// Palm positions as points and approach axes as short lines, one draw call each.
TM.mapGlyphs = function (m, idx) {
  const { G, palms, approach, scale, clusterOf } = m;
  const pos = [], col = [], line = [], lcol = [];
  const len = 0.12 * scale;
  idx.forEach((i) => {
    const p = new THREE.Vector3().setFromMatrixPosition(palms[i]);
    const a = approach.clone().transformDirection(palms[i]);
    const c = new THREE.Color(TM.clusterColor(clusterOf(i)));
    pos.push(p.x, p.y, p.z);
    col.push(c.r, c.g, c.b);
    line.push(p.x - a.x * len, p.y - a.y * len, p.z - a.z * len, p.x, p.y, p.z);
    lcol.push(c.r, c.g, c.b, c.r, c.g, c.b);
  });
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.Float32BufferAttribute(pos, 3));
  g.setAttribute('color', new THREE.Float32BufferAttribute(col, 3));
  const points = new THREE.Points(g, new THREE.PointsMaterial({ size: 5, sizeAttenuation: false, vertexColors: THREE.VertexColors }));
  points.userData.index = idx;
  const lg = new THREE.BufferGeometry();
  lg.setAttribute('position', new THREE.Float32BufferAttribute(line, 3));
  lg.setAttribute('color', new THREE.Float32BufferAttribute(lcol, 3));
  const group = new THREE.Group();
  group.add(points, new THREE.LineSegments(lg, new THREE.LineBasicMaterial({ vertexColors: THREE.VertexColors })));
  group.userData.points = points;
  return group;
};
// Representatives: larger dark markers.
TM.mapRepMarkers = function (m, idx) {
  const { palms, reps } = m;
  const pos = [];
  idx.filter((i) => reps.has(i)).forEach((i) => {
    const p = new THREE.Vector3().setFromMatrixPosition(palms[i]);
    pos.push(p.x, p.y, p.z);
  });
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.Float32BufferAttribute(pos, 3));
  return new THREE.Points(g, new THREE.PointsMaterial({ size: 11, sizeAttenuation: false, color: 0x111111 }));
};
// Contacts of grasp i: red balls and their normals.
TM.mapContacts = function (m, i) {
  const { G, scale } = m;
  const group = new THREE.Group();
  const ball = new THREE.SphereBufferGeometry(0.025 * scale, 10, 8);
  const red = new THREE.MeshLambertMaterial({ color: 0xd01010 });
  const line = [];
  TM.contactsOf(G, i).forEach((k) => {
    const p = new THREE.Vector3(G.cp[3 * k], G.cp[3 * k + 1], G.cp[3 * k + 2]);
    const dot = new THREE.Mesh(ball, red);
    dot.position.copy(p);
    group.add(dot);
    line.push(p.x, p.y, p.z, p.x + G.cn[3 * k] * 0.25 * scale, p.y + G.cn[3 * k + 1] * 0.25 * scale, p.z + G.cn[3 * k + 2] * 0.25 * scale);
  });
  const lg = new THREE.BufferGeometry();
  lg.setAttribute('position', new THREE.Float32BufferAttribute(line, 3));
  group.add(new THREE.LineSegments(lg, new THREE.LineBasicMaterial({ color: 0xd01010 })));
  return group;
};
// The numbers of grasp i in the details box; returns the names of the links that touch.
TM.mapDetails = function (m, box, i) {
  const { D, G, reps, clusterOf, linkName } = m;
  box.textContent = '';
  if (i < 0) return;
  const c = clusterOf(i);
  box.appendChild(TM.el('h2', {}, 'grasp ' + i + (reps.has(i) ? ' (representative)' : '')));
  const t = TM.el('table');
  const row = (k, val) => { const r = TM.el('tr'); r.appendChild(TM.el('th', {}, k)); r.appendChild(TM.el('td', {}, val)); t.appendChild(r); };
  row('cluster', c === null ? 'none' : c < 0 ? 'outlier' : String(c));
  row('epsilon', TM.fmt(G.eps[i], 5));
  row('volume', G.vol[i].toExponential(3));
  row('force closure', G.fc[i] ? 'yes' : 'no');
  if (D.hold) row('hold (' + D.hold.engine + ')', D.hold.labels[i] + (D.hold.translation[i] >= 0 ? ', moved ' + TM.fmt(D.hold.translation[i] * 1000, 1) + ' mm' : ''));
  row('position (m)', [0, 1, 2].map((k) => TM.fmt(G.pose[7 * i + k], 4)).join(' '));
  row('quaternion', [3, 4, 5, 6].map((k) => TM.fmt(G.pose[7 * i + k], 4)).join(' '));
  box.appendChild(t);
  const J = D.joint_names.length;
  box.appendChild(TM.el('div', { class: 'tm-note' }, 'joints: ' +
    D.joint_names.map((name, k) => name + ' ' + TM.fmt(G.joints[i * J + k], 3)).join(', ')));
  const cs = TM.contactsOf(G, i);
  box.appendChild(TM.el('h2', {}, cs.length + ' contacts'));
  const ct = TM.el('table');
  const head = TM.el('tr');
  ['link', 'point (m)', 'normal', 'depth (mm)'].forEach((h) => head.appendChild(TM.el('th', {}, h)));
  ct.appendChild(head);
  const touching = new Set();
  cs.forEach((k) => {
    const r = TM.el('tr');
    touching.add(linkName(G.cl[k]));
    r.appendChild(TM.el('td', {}, linkName(G.cl[k])));
    r.appendChild(TM.el('td', {}, [0, 1, 2].map((a) => TM.fmt(G.cp[3 * k + a], 3)).join(' ')));
    r.appendChild(TM.el('td', {}, [0, 1, 2].map((a) => TM.fmt(G.cn[3 * k + a], 2)).join(' ')));
    r.appendChild(TM.el('td', {}, TM.fmt(G.cd[k] * 1000, 2)));
    ct.appendChild(r);
  });
  box.appendChild(ct);
  box.appendChild(TM.el('div', { class: 'tm-note' }, 'touching: ' + ([...touching].join(', ') || 'none')));
  return touching;
};
TM.run(function () {
  const D = TM.data, G = D.grasps, n = G.n;
  const hand = D.hand ? TM.prepareHand(D.hand) : null;
  const ui = TM.layout();
  if (TM.hash.details === '0') ui.details.style.display = 'none';
  const v = TM.viewer(ui.view);
  const object = TM.objectMesh(D.object);
  v.scene.add(object);
  const ob = TM.bounds(D.object.v);
  const scale = ob.radius;
  const approach = new THREE.Vector3().fromArray(hand ? hand.approach : [0, 0, 1]);
  const clusterOf = (i) => (G.cluster ? G.cluster[i] : null);
  const reps = new Set(D.clusters.map((c) => c.rep));
  const palms = [];
  for (let i = 0; i < n; ++i) palms.push(TM.poseMatrix(G.pose, i));
  const state = { cluster: 'all', eps: 0, hold: 'all', ghosts: TM.hash.ghosts === '1', selected: -1 };
  const layers = { glyphs: null, reps: null, ghosts: null, hand: null, contacts: null };
  const filtered = () => {
    const out = [];
    for (let i = 0; i < n; ++i) {
      const c = clusterOf(i);
      if (state.cluster !== 'all' && String(c) !== state.cluster) continue;
      if (G.eps[i] < state.eps) continue;
      if (D.hold && state.hold !== 'all' && D.hold.labels[i] !== state.hold) continue;
      out.push(i);
    }
    return out;
  };
  const swap = (name, obj) => {
    if (layers[name]) v.scene.remove(layers[name]);
    layers[name] = obj;
    if (obj) v.scene.add(obj);
  };
  const placedHand = (i, material) => {
    const g = TM.handGroup(hand, G.joints.slice(i * hand.joint_names.length, (i + 1) * hand.joint_names.length), material);
    g.matrixAutoUpdate = false;
    g.matrix.copy(palms[i]);
    return g;
  };
  const ghostHands = (idx) => {
    if (!hand || !state.ghosts) return null;
    const group = new THREE.Group();
    const mats = {};
    idx.slice(0, D.ghost_limit).forEach((i) => {
      const c = TM.clusterColor(clusterOf(i));
      mats[c] = mats[c] || TM.handMaterial(c, true);
      group.add(placedHand(i, mats[c]));
    });
    return group;
  };
  const linkName = (l) => (l >= 0 && l < D.link_names.length ? D.link_names[l]
    : hand && l >= 0 && l < hand.links.length ? hand.links[l].name : 'link ' + l);
  const m = { D, G, hand, palms, approach, scale, clusterOf, reps, linkName };
  const select = (i) => {
    state.selected = i;
    swap('hand', null);
    swap('contacts', null);
    document.querySelectorAll('.tm-list div').forEach((e) => e.classList.toggle('sel', e.dataset.i === String(i)));
    const touching = TM.mapDetails(m, ui.details, i);
    if (i >= 0) {
      if (hand) {
        const base = TM.handMaterial(TM.clusterColor(clusterOf(i)), false);
        const touch = TM.handMaterial(new THREE.Color(TM.clusterColor(clusterOf(i))).lerp(new THREE.Color(0xffc000), 0.6), false);
        const h = placedHand(i, base);
        h.children.forEach((lg) => { if (touching.has(hand.links[lg.userData.link].name)) lg.children.forEach((m) => { m.material = touch; }); });
        swap('hand', h);
      }
      swap('contacts', TM.mapContacts(m, i));
      const p = new THREE.Vector3().setFromMatrixPosition(palms[i]).project(v.camera);
      document.body.setAttribute('data-palm', TM.fmt((p.x + 1) / 2, 4) + ' ' + TM.fmt((1 - p.y) / 2, 4));
    }
    v.render();
  };
  TM.mapUi(ui.side, D, state, filtered, () => refresh(), select, reps, clusterOf);
  let listed = [];
  const refresh = () => {
    listed = TM.fillList(ui.side.querySelector('.tm-list'), filtered(), G, reps, clusterOf, select, state.selected);
    swap('glyphs', TM.mapGlyphs(m, listed));
    swap('reps', TM.mapRepMarkers(m, listed));
    swap('ghosts', ghostHands(listed));  // the best epsilon first
    v.render();
    return listed.length;
  };
  const drawn = refresh();
  // Clicks (not drags) pick the nearest palm glyph.
  const ray = new THREE.Raycaster();
  ray.params.Points.threshold = 0.04 * scale;
  let down = null;
  v.renderer.domElement.addEventListener('pointerdown', (e) => { down = [e.clientX, e.clientY]; });
  v.renderer.domElement.addEventListener('pointerup', (e) => {
    if (!down || Math.hypot(e.clientX - down[0], e.clientY - down[1]) > 4) return;
    const r = v.renderer.domElement.getBoundingClientRect();
    ray.setFromCamera(new THREE.Vector2(((e.clientX - r.left) / r.width) * 2 - 1, -((e.clientY - r.top) / r.height) * 2 + 1), v.camera);
    const hits = ray.intersectObject(layers.glyphs.userData.points);
    if (hits.length) select(layers.glyphs.userData.points.userData.index[hits[0].index]);
  });
  const sceneRadius = scale + (hand ? hand.reach : 0.1 * scale);
  v.look(ob.center, 0.8 * sceneRadius, TM.hash.view || 'iso');
  let first = TM.hash.grasp !== undefined ? Number(TM.hash.grasp) : -1;
  if (first < 0 && n > 0) first = D.clusters.length ? D.clusters[0].rep : listed[0];
  select(first >= 0 && first < n ? first : -1);
  TM.ready(v, drawn);
});
