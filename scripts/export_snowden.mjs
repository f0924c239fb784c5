#!/usr/bin/env node
// Export the two Snowden-bust meshes shipped inside the npm package `snowden`
// (v1.0.1) as PLY files.
//
// The package stores each mesh as a CommonJS module whose `positions` and
// `cells` are base64-encoded Float32/Uint32 arrays, decoded on require():
//   hi.js (== index.js, the package main)  54,559 vertices, 109,259 triangles
//   lo.js                                  18,743 vertices,  37,629 triangles
// Coordinates are written exactly as the package provides them (its build
// step already rotated the original OBJ: y' = -z, z' = -y, and flipped the
// triangle winding to match).
//
// Usage: node export_snowden.mjs <unpacked-snowden-package-dir> <out-dir> [--binary]
//   Writes <out-dir>/snowden_54559.ply and <out-dir>/snowden_18743.ply.
//   Default is ASCII PLY (float32 values printed with the fewest digits that
//   round-trip exactly); --binary writes binary_little_endian 1.0 instead.
//   Files are written to a temporary name and renamed, so a partially written
//   file never appears under the final name. Exits non-zero on any mismatch.

import { createRequire } from 'node:module';
import fs from 'node:fs';
import path from 'node:path';

const MESHES = [
  { module: 'hi.js', vertices: 54559, out: 'snowden_54559.ply' },
  { module: 'lo.js', vertices: 18743, out: 'snowden_18743.ply' },
];

function die(msg) {
  process.stderr.write(`export_snowden: ERROR: ${msg}\n`);
  process.exit(1);
}

const args = process.argv.slice(2);
const binary = args.includes('--binary');
const positional = args.filter((a) => !a.startsWith('--'));
if (positional.length !== 2) {
  die('usage: export_snowden.mjs <snowden-package-dir> <out-dir> [--binary]');
}
const [pkgDir, outDir] = positional.map((p) => path.resolve(p));

let pkgJson;
try {
  pkgJson = JSON.parse(fs.readFileSync(path.join(pkgDir, 'package.json'), 'utf8'));
} catch (e) {
  die(`cannot read ${path.join(pkgDir, 'package.json')}: ${e.message}`);
}
if (pkgJson.name !== 'snowden') die(`${pkgDir} is package '${pkgJson.name}', expected 'snowden'`);
fs.mkdirSync(outDir, { recursive: true });

// The package's loader uses the deprecated `new Buffer()`; keep stderr quiet.
process.noDeprecation = true;
const require = createRequire(path.join(pkgDir, 'package.json'));

// Shortest decimal string that parses back to the same float32 value.
function f32str(v) {
  for (let p = 6; p < 9; p++) {
    const s = Number(v.toPrecision(p)).toString();
    if (Math.fround(Number(s)) === v) return s;
  }
  return Number(v.toPrecision(9)).toString();
}

function header(nv, nf, format) {
  return [
    'ply',
    `format ${format} 1.0`,
    `comment Snowden bust, npm package snowden@${pkgJson.version} (${pkgJson.license ?? 'no licence field'}), exported by glovesculpt scripts/export_snowden.mjs`,
    `element vertex ${nv}`,
    'property float x',
    'property float y',
    'property float z',
    `element face ${nf}`,
    'property list uchar int vertex_indices',
    'end_header',
    '',
  ].join('\n');
}

function encodeAscii(positions, cells) {
  const parts = [header(positions.length, cells.length, 'ascii')];
  const lines = new Array(positions.length + cells.length);
  let j = 0;
  for (const p of positions) lines[j++] = `${f32str(p[0])} ${f32str(p[1])} ${f32str(p[2])}`;
  for (const c of cells) lines[j++] = `3 ${c[0]} ${c[1]} ${c[2]}`;
  parts.push(lines.join('\n'), '\n');
  return Buffer.from(parts.join(''), 'latin1');
}

function encodeBinary(positions, cells) {
  const head = Buffer.from(header(positions.length, cells.length, 'binary_little_endian'), 'latin1');
  const body = Buffer.alloc(positions.length * 12 + cells.length * 13);
  let o = 0;
  for (const p of positions) {
    body.writeFloatLE(p[0], o); body.writeFloatLE(p[1], o + 4); body.writeFloatLE(p[2], o + 8);
    o += 12;
  }
  for (const c of cells) {
    body.writeUInt8(3, o);
    body.writeInt32LE(c[0], o + 1); body.writeInt32LE(c[1], o + 5); body.writeInt32LE(c[2], o + 9);
    o += 13;
  }
  return Buffer.concat([head, body]);
}

for (const m of MESHES) {
  let mesh;
  try {
    mesh = require(path.join(pkgDir, m.module));
  } catch (e) {
    die(`cannot load ${m.module} from ${pkgDir}: ${e.message}`);
  }
  const { positions, cells } = mesh;
  if (!Array.isArray(positions) || !Array.isArray(cells)) {
    die(`${m.module} does not export positions/cells arrays`);
  }
  if (positions.length !== m.vertices) {
    die(`${m.module} has ${positions.length} vertices, expected ${m.vertices}`);
  }
  for (let i = 0; i < positions.length; i++) {
    const p = positions[i];
    if (p.length !== 3 || !p.every(Number.isFinite)) die(`${m.module}: bad vertex ${i}`);
  }
  for (let i = 0; i < cells.length; i++) {
    const c = cells[i];
    if (c.length !== 3 || !c.every((k) => Number.isInteger(k) && k >= 0 && k < positions.length)) {
      die(`${m.module}: bad face ${i}: ${JSON.stringify(Array.from(c))}`);
    }
  }

  const data = binary ? encodeBinary(positions, cells) : encodeAscii(positions, cells);
  const dst = path.join(outDir, m.out);
  const tmp = path.join(outDir, `.${m.out}.partial.${process.pid}`);
  try {
    fs.writeFileSync(tmp, data);
    fs.renameSync(tmp, dst);
  } catch (e) {
    try { fs.rmSync(tmp, { force: true }); } catch { /* ignore */ }
    die(`cannot write ${dst}: ${e.message}`);
  }
  process.stdout.write(`${m.out} ${positions.length} ${cells.length}\n`);
}
