// Runs in headless Chromium (threejs_lights.mjs serves it): three.js itself loads the HDRI
// and lumis's glTF lights and shows what a user of both would see.
//   1. The sun: a camera aimed at the brightest light renders the HDRI as scene.background;
//      the brightest thing in view must be the map's sun, at the centre of the view.
//   2. A Lambert sphere lit by the lights alone against the same sphere lit by the HDRI
//      alone (scene.environment, which three.js turns into a PMREM), seen from the six axis
//      directions: the mean colour of 5 regions of each view (a centre disk and 4 quadrants
//      of the rim) must agree.
// Everything is rendered into float render targets without tone mapping: linear radiance.
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { HDRLoader } from 'three/addons/loaders/HDRLoader.js';
import { EXRLoader } from 'three/addons/loaders/EXRLoader.js';

const luminance = (r, g, b) => 0.2126 * r + 0.7152 * g + 0.0722 * b;

function readTarget(renderer, target) {
  const w = target.width, h = target.height;
  const px = new Float32Array(4 * w * h);
  renderer.readRenderTargetPixels(target, 0, 0, w, h, px);
  return px; // row 0 is the bottom of the view (WebGL)
}

// The lights of a glTF file as three.js placed them: world direction towards each light
// (light position minus target position) and its colour x intensity.
async function loadLights(url) {
  const gltf = await new GLTFLoader().loadAsync(url);
  gltf.scene.updateMatrixWorld(true);
  const lights = [];
  gltf.scene.traverse((o) => {
    if (!o.isDirectionalLight) return;
    const p = new THREE.Vector3(), t = new THREE.Vector3();
    o.getWorldPosition(p);
    o.target.getWorldPosition(t);
    const c = o.color.clone().multiplyScalar(o.intensity);
    lights.push({ object: o, toLight: p.sub(t).normalize(), rgb: [c.r, c.g, c.b] });
  });
  return { scene: gltf.scene, lights, extras: gltf.parser.json.asset.extras || {} };
}

// 1. Aim a narrow camera at dir and render the background: the brightest pixel's angle from
// the view axis and its luminance.
function lookAt(renderer, background, dir, size, fovDeg) {
  const scene = new THREE.Scene();
  scene.background = background;
  const camera = new THREE.PerspectiveCamera(fovDeg, 1, 0.1, 10);
  camera.position.set(0, 0, 0);
  camera.up.set(Math.abs(dir.y) > 0.99 ? 1 : 0, Math.abs(dir.y) > 0.99 ? 0 : 1, 0);
  camera.lookAt(dir);
  camera.updateMatrixWorld(true);
  const target = new THREE.WebGLRenderTarget(size, size, { type: THREE.FloatType });
  renderer.setRenderTarget(target);
  renderer.render(scene, camera);
  renderer.setRenderTarget(null);
  const px = readTarget(renderer, target);
  target.dispose();
  let best = -1, bx = 0, by = 0;
  for (let y = 0; y < size; y++)
    for (let x = 0; x < size; x++) {
      const k = 4 * (y * size + x);
      const l = luminance(px[k], px[k + 1], px[k + 2]);
      if (l > best) { best = l; bx = x; by = y; }
    }
  const ndc = new THREE.Vector3((2 * (bx + 0.5)) / size - 1, (2 * (by + 0.5)) / size - 1, 0.5);
  const ray = ndc.unproject(camera).sub(camera.position).normalize();
  return { luminance: best, angleDeg: THREE.MathUtils.radToDeg(ray.angleTo(dir)), pixel: [bx, by] };
}

// 2. The sphere from the six axis directions (orthographic, size x size each): per view the
// mean RGB of 5 regions of its disk.
function sphereRegions(renderer, scene, size) {
  const views = [[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]];
  const regions = [];
  const target = new THREE.WebGLRenderTarget(size, size, { type: THREE.FloatType });
  for (const v of views) {
    const camera = new THREE.OrthographicCamera(-1.05, 1.05, 1.05, -1.05, 0.1, 10);
    camera.position.set(3 * v[0], 3 * v[1], 3 * v[2]);
    if (v[1] !== 0) camera.up.set(0, 0, -1); // looking along y: any up but y
    camera.lookAt(0, 0, 0);
    renderer.setRenderTarget(target);
    renderer.render(scene, camera);
    renderer.setRenderTarget(null);
    const px = readTarget(renderer, target);
    const sums = Array.from({ length: 5 }, () => [0, 0, 0, 0]);
    for (let y = 0; y < size; y++)
      for (let x = 0; x < size; x++) {
        const sx = (1.05 * (2 * (x + 0.5))) / size - 1.05, sy = (1.05 * (2 * (y + 0.5))) / size - 1.05;
        const r = Math.hypot(sx, sy);
        if (r > 0.95) continue; // off the sphere and its silhouette's edge
        const region = r < 0.5 ? 0 : 1 + (sx >= 0 ? 1 : 0) + (sy >= 0 ? 2 : 0);
        const k = 4 * (y * size + x);
        for (let c = 0; c < 3; c++) sums[region][c] += px[k + c];
        sums[region][3]++;
      }
    for (const s of sums) regions.push([s[0] / s[3], s[1] / s[3], s[2] / s[3]]);
  }
  target.dispose();
  return regions;
}

function sphereScene(material) {
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(0, 0, 0);
  scene.add(new THREE.Mesh(new THREE.SphereGeometry(1, 128, 64), material));
  return scene;
}

// The worst difference of the regions' mean luminance, relative to the mean over all
// regions of the IBL's (so that a dark region does not dominate), and per-region numbers.
function compareRegions(lit, ibl) {
  const yl = lit.map((c) => luminance(...c)), yi = ibl.map((c) => luminance(...c));
  const mean = yi.reduce((a, b) => a + b, 0) / yi.length;
  let worst = 0;
  for (let k = 0; k < yl.length; k++) worst = Math.max(worst, Math.abs(yl[k] - yi[k]) / mean);
  const ratio = yl.reduce((a, b) => a + b, 0) / yi.reduce((a, b) => a + b, 0);
  return { worst, ratio, lights: yl, ibl: yi };
}

// The map's brightest pixel (the sun) and where three.js's equirectUv sends a direction:
// u = atan2(z, x) / 2 pi + 1/2, v = asin(y) / pi + 1/2 (v from the bottom; HDRLoader's
// flipY puts the file's first row at v = 1), as file column and row.
function mapSun(texture) {
  const { data, width, height } = texture.image;
  let best = -1, bi = 0, bj = 0;
  for (let j = 0; j < height; j++)
    for (let i = 0; i < width; i++) {
      const k = 4 * (j * width + i);
      const l = luminance(data[k], data[k + 1], data[k + 2]);
      if (l > best) { best = l; bi = i; bj = j; }
    }
  // data row 0 goes to v = 1 with flipY (HDRLoader), to v = 0 without (EXRLoader, which
  // stores the file's rows bottom up): as the file's row, 0 the top
  if (!texture.flipY) bj = height - 1 - bj;
  return { luminance: best, pixel: [bi, bj], width, height };
}

function equirectPixel(dir, width, height) {
  const u = Math.atan2(dir.z, dir.x) / (2 * Math.PI) + 0.5;
  const v = Math.asin(Math.min(1, Math.max(-1, dir.y))) / Math.PI + 0.5;
  return [u * width, (1 - v) * height];
}

async function run(config) {
  const canvas = document.createElement('canvas');
  const renderer = new THREE.WebGLRenderer({ canvas, antialias: false });
  renderer.toneMapping = THREE.NoToneMapping;
  if (!renderer.extensions.has('EXT_color_buffer_float'))
    throw new Error('WebGL2 without EXT_color_buffer_float: cannot read linear radiance');
  const Loader = config.hdr.toLowerCase().endsWith('.exr') ? EXRLoader : HDRLoader;
  const hdr = await new Loader().setDataType(THREE.FloatType).loadAsync(config.hdr);
  hdr.mapping = THREE.EquirectangularReflectionMapping;
  const sun = mapSun(hdr);
  const gl = renderer.getContext();
  const out = { three: THREE.REVISION, renderer: gl.getParameter(gl.VERSION), sun, files: [] };

  // the HDRI alone: background for the sun check, environment (PMREM) for the sphere
  const iblScene = sphereScene(new THREE.MeshLambertMaterial({ color: 0xffffff }));
  iblScene.environment = hdr;
  const ibl = sphereRegions(renderer, iblScene, config.size);

  for (const file of config.gltf) {
    const { scene: lightsScene, lights, extras } = await loadLights(file);
    let brightest = lights[0];
    for (const l of lights) if (luminance(...l.rgb) > luminance(...brightest.rgb)) brightest = l;
    const view = lookAt(renderer, hdr, brightest.toLight, 64, 20);
    const [pu, pv] = equirectPixel(brightest.toLight, sun.width, sun.height);
    let du = Math.abs(pu - (sun.pixel[0] + 0.5));
    du = Math.min(du, sun.width - du);
    const dv = Math.abs(pv - (sun.pixel[1] + 0.5));

    const litScene = sphereScene(new THREE.MeshLambertMaterial({ color: 0xffffff }));
    litScene.add(lightsScene);
    const lit = sphereRegions(renderer, litScene, config.size);
    out.files.push({
      file, frame: extras.frame, lights: lights.length,
      brightest: brightest.toLight.toArray(),
      view,
      sunRatio: view.luminance / sun.luminance,
      equirectPixel: [pu, pv], pixelDistance: Math.hypot(du, dv),
      sphere: compareRegions(lit, ibl),
    });
  }
  renderer.dispose();
  return out;
}

window.lumisRun = (config) => run(config).catch((e) => ({ error: String(e && e.stack || e) }));
window.lumisReady = true;
