// The three.js consumer test of lumis's glTF lights (docs/lights-export.md, "Tests in the
// consumers"): headless Chromium (Debian's, driven by playwright-core) loads three.js, the
// HDRI and the glTF files in threejs_page.mjs, which reports what three.js shows.
//
//   node threejs_lights.mjs --hdr MAP.hdr [--hdr MAP.exr] --expect-pass A.gltf
//                           --expect-fail B.gltf [--size N]
//
// With each map (HDRLoader for .hdr, EXRLoader for .exr), each --expect-pass file must (1) have its brightest light where three.js shows the map's
// sun: a 20-degree camera aimed at it sees the sun within SUN_DEG of the centre, at least
// SUN_SHARE of the map's peak luminance; and (2) light a Lambert sphere as the HDRI does as
// three.js's environment (PMREM): every region within SPHERE_TOL of the mean (compareRegions).
// Each --expect-fail file (the same lights in the other frame) must fail both: the test
// proves on every run that it can tell the frames apart.  Exit 0 pass, 1 fail, 77 skip
// (no chromium).
import { chromium } from 'playwright-core';
import { existsSync, readFileSync } from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

// Measured (docs/lights-export.md) on blender-sunrise at 256 x 128 with 16 Wu lights: the
// engine frame's sun 0.22 degrees off the centre at 75 % of the map's peak (the background's
// cube map filters it), its worst region 8.3 % of the mean (7.0-8.5 % with 8 to 64 lights:
// PMREM's irradiance is its blurriest mip, not a cosine lobe); the other frame's worst
// region 267 %, its sun out of view.
const SUN_DEG = 3.0, SUN_SHARE = 0.25, SPHERE_TOL = 0.15;

const here = path.dirname(fileURLToPath(import.meta.url));
const args = { pass: [], fail: [], size: 48, hdr: [] };
for (let i = 2; i < process.argv.length; i++) {
  const a = process.argv[i], v = process.argv[i + 1];
  if (a === '--hdr') { args.hdr.push(v); i++; }
  else if (a === '--expect-pass') { args.pass.push(v); i++; }
  else if (a === '--expect-fail') { args.fail.push(v); i++; }
  else if (a === '--size') { args.size = Number(v); i++; }
  else { console.error(`threejs_lights: unknown argument ${a}`); process.exit(2); }
}
if (args.hdr.length === 0 || args.pass.length === 0) {
  console.error('usage: node threejs_lights.mjs --hdr MAP.hdr --expect-pass A.gltf [--expect-fail B.gltf]');
  process.exit(2);
}
const exe = process.env.LUMIS_CHROMIUM || '/usr/bin/chromium';
if (!existsSync(exe)) {
  console.log(`SKIP: no ${exe} (scripts/install-deps.sh --dev installs chromium)`);
  process.exit(77);
}

// Everything under one made-up origin, answered from the disk: the page, three.js, the data.
const files = new Map([
  ['/page.html', { body: '<!doctype html><script type="importmap">{"imports":{"three":"/three/build/three.module.js","three/addons/":"/three/examples/jsm/"}}</script><script type="module" src="/page.mjs"></script>', type: 'text/html' }],
  ['/page.mjs', { file: path.join(here, 'threejs_page.mjs') }],
]);
const data = [...args.hdr, ...args.pass, ...args.fail].map((f, k) => {
  const url = `/data/${k}-${path.basename(f)}`;
  files.set(url, { file: f });
  return url;
});
const mime = (f) => (f.endsWith('.js') || f.endsWith('.mjs') ? 'text/javascript'
  : f.endsWith('.gltf') ? 'model/gltf+json' : f.endsWith('.glb') ? 'model/gltf-binary'
  : 'application/octet-stream');

const t0 = Date.now();
const browser = await chromium.launch({
  executablePath: exe,
  args: ['--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist', '--no-sandbox'],
});
let failed = 0;
try {
  const page = await browser.newPage();
  page.on('console', (m) => { if (m.type() === 'error') console.log(`page: ${m.text()}`); });
  page.on('pageerror', (e) => console.log(`page error: ${e}`));
  await page.route('http://lumis.test/**', (route) => {
    const p = new URL(route.request().url()).pathname;
    let f = files.get(p);
    if (!f && p.startsWith('/three/')) f = { file: path.join(here, 'node_modules', p.slice(1)) };
    if (f && f.body) return route.fulfill({ status: 200, contentType: f.type, body: f.body });
    if (f && existsSync(f.file))
      return route.fulfill({ status: 200, contentType: f.type || mime(f.file), body: readFileSync(f.file) });
    return route.fulfill({ status: 404, body: 'not found' });
  });
  await page.goto('http://lumis.test/page.html');
  await page.waitForFunction(() => window.lumisReady === true, null, { timeout: 60000 });
  for (let m = 0; m < args.hdr.length; m++) {
    const r = await page.evaluate((c) => window.lumisRun(c), {
      hdr: data[m], gltf: data.slice(args.hdr.length), size: args.size,
    });
    if (r.error) throw new Error(r.error);
    console.log(`${path.basename(args.hdr[m])}: three.js r${r.three} on ${r.renderer}; map sun at ` +
      `pixel (${r.sun.pixel}) of ${r.sun.width} x ${r.sun.height}, luminance ` +
      `${r.sun.luminance.toPrecision(5)}`);
    r.files.forEach((f, k) => {
      const expectPass = k < args.pass.length;
      const name = expectPass ? args.pass[k] : args.fail[k - args.pass.length];
      const sunOk = f.view.angleDeg <= SUN_DEG && f.sunRatio >= SUN_SHARE;
      const sphereOk = f.sphere.worst <= SPHERE_TOL;
      console.log(`${path.basename(name)} (frame ${f.frame}, ${f.lights} lights): brightest light ` +
        `towards (${f.brightest.map((x) => x.toFixed(4))})`);
      console.log(`  sun: aimed at it, three.js shows its brightest pixel ${f.view.angleDeg.toFixed(2)} deg ` +
        `off the centre at ${(100 * f.sunRatio).toFixed(1)} % of the map's peak ` +
        `(pass: <= ${SUN_DEG} deg, >= ${100 * SUN_SHARE} %); equirectUv puts it ` +
        `${f.pixelDistance.toFixed(2)} px from the sun's pixel`);
      console.log(`  sphere: lights / IBL mean ${f.sphere.ratio.toFixed(4)}, worst of ` +
        `${f.sphere.lights.length} regions ${(100 * f.sphere.worst).toFixed(2)} % of the mean ` +
        `(pass: <= ${100 * SPHERE_TOL} %)`);
      if (expectPass && !(sunOk && sphereOk)) {
        console.log(`FAIL: ${name} should line up with ${args.hdr[m]} in three.js and does not`);
        failed++;
      }
      if (!expectPass && (sunOk || sphereOk)) {
        console.log(`FAIL: ${name} (the other frame) ${sunOk ? 'passes the sun check' : ''}` +
          `${sunOk && sphereOk ? ' and ' : ''}${sphereOk ? 'passes the sphere check' : ''}: ` +
          'the test cannot tell the frames apart');
        failed++;
      }
    });
  }
} finally {
  await browser.close();
}
console.log(`${failed ? 'FAIL' : 'PASS'} in ${((Date.now() - t0) / 1000).toFixed(1)} s`);
process.exit(failed ? 1 : 0);
