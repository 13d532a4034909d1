// SPDX-License-Identifier: MIT
// Converts the Stanford bunny (public domain, npm package `bunny`) into a
// BOP model: millimetres, centred on its bounding box, with vertex normals.
// Usage: (cd /tmp && npm pack bunny && tar xzf bunny-*.tgz)
//        node toolchain/make-bunny-model.js /tmp/package config/models 20
// The result is committed in config/models, so builds never fetch it.
'use strict';
const fs = require('fs');
const path = require('path');

const [pkgDir, outDir, objIdArg] = process.argv.slice(2);
if (!pkgDir || !outDir) {
	console.error('usage: make-bunny-model.js BUNNY_PACKAGE_DIR OUT_DIR [OBJ_ID]');
	process.exit(2);
}
const objId = parseInt(objIdArg || '20', 10);
const bunny = require(path.resolve(pkgDir));
const P = bunny.positions, C = bunny.cells;

// The real bunny is about 155 mm wide; scale its largest extent to that.
const min = [Infinity, Infinity, Infinity], max = [-Infinity, -Infinity, -Infinity];
for (const p of P) for (let k = 0; k < 3; k++) { min[k] = Math.min(min[k], p[k]); max[k] = Math.max(max[k], p[k]); }
const extent = Math.max(...[0, 1, 2].map(k => max[k] - min[k]));
const scale = 155.0 / extent;
const centre = [0, 1, 2].map(k => 0.5 * (min[k] + max[k]));
const V = P.map(p => [0, 1, 2].map(k => (p[k] - centre[k]) * scale));

// Area-weighted vertex normals.
const N = V.map(() => [0, 0, 0]);
for (const [a, b, c] of C) {
	const u = [0, 1, 2].map(k => V[b][k] - V[a][k]);
	const w = [0, 1, 2].map(k => V[c][k] - V[a][k]);
	const n = [u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]];
	for (const i of [a, b, c]) for (let k = 0; k < 3; k++) N[i][k] += n[k];
}
for (const n of N) { const l = Math.hypot(...n) || 1; for (let k = 0; k < 3; k++) n[k] /= l; }

let out = `ply\nformat ascii 1.0\ncomment Stanford bunny (public domain), mm\nelement vertex ${V.length}\n` +
	'property float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty float nz\n' +
	`element face ${C.length}\nproperty list uchar int vertex_indices\nend_header\n`;
out += V.map((v, i) => `${v.map(x => x.toFixed(4)).join(' ')} ${N[i].map(x => x.toFixed(5)).join(' ')}`).join('\n') + '\n';
out += C.map(f => `3 ${f.join(' ')}`).join('\n') + '\n';
const name = `obj_${String(objId).padStart(6, '0')}.ply`;
fs.mkdirSync(outDir, { recursive: true });
fs.writeFileSync(path.join(outDir, name), out);

// Diameter: exact max distance between vertices.
let d2 = 0;
for (let i = 0; i < V.length; i++) for (let j = i + 1; j < V.length; j++) {
	const dx = V[i][0] - V[j][0], dy = V[i][1] - V[j][1], dz = V[i][2] - V[j][2];
	d2 = Math.max(d2, dx * dx + dy * dy + dz * dz);
}
const vmin = [0, 1, 2].map(k => Math.min(...V.map(v => v[k])));
const vmax = [0, 1, 2].map(k => Math.max(...V.map(v => v[k])));
const info = {};
info[String(objId)] = {
	diameter: +Math.sqrt(d2).toFixed(4),
	min_x: +vmin[0].toFixed(4), min_y: +vmin[1].toFixed(4), min_z: +vmin[2].toFixed(4),
	size_x: +(vmax[0] - vmin[0]).toFixed(4), size_y: +(vmax[1] - vmin[1]).toFixed(4), size_z: +(vmax[2] - vmin[2]).toFixed(4),
};
fs.writeFileSync(path.join(outDir, 'models_info.json'), JSON.stringify(info, null, 2) + '\n');
console.log(`${name}: ${V.length} vertices, ${C.length} faces, diameter ${info[String(objId)].diameter} mm`);
