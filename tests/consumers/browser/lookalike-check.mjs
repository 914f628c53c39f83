#!/usr/bin/env node
// lookalike-check.mjs REPORT VIEW OURS_PNG OUT_PREFIX [--max-false-share F] [--max-mean-de X]
//                     [--max-median-de Y] [--max-sky-in-ours S]
// lookalike-check.mjs --self-test
//
// Compares what three.js showed of a city.glb (REPORT: run-page.mjs's output for lookalike.html;
// its view VIEW) with `dawnforge render`'s picture of the same view (OURS_PNG). It shares no code
// with dawnforge: PNG, sRGB -> CIELAB and CIEDE2000 are all here.
//
// The pixels compared ("geometry"): three's mask says a surface was drawn there and at its 8
// neighbours (silhouettes, where anti-aliasing and our LOD switch differ, are left out), and our
// picture shows a surface there too. Our picture's sky is found without asking the renderer: per
// row, the median colour of our pixels where three's mask says sky (same camera, same file, so
// the same sky there); a geometry pixel of ours within ΔE00 2 of its row's sky colour counts as
// sky in ours and is left out (`sky_in_ours`: their share; a large one means the two pictures do
// not show the same scene, which fails).
//
// Figures, over the geometry pixels:
//   de_mean, de_median, de_p90   CIEDE2000 between the two pictures (sRGB as written, D65, 2°)
//   dL_mean                      mean L* of three's picture minus ours (exposure or light off)
//   false_share                  the share of three's pixels in false colours: a colour no lit
//                                surface of a city has, a material-ID code shown as a colour. A
//                                pixel is one when its HSV hue is within 15° of red, yellow, green,
//                                cyan, blue or magenta (0, 60, ..., 300°) and its CIELAB chroma C*
//                                is at least 0.7 × the chroma of that pure sRGB colour (R 104.6,
//                                Y 96.9, G 119.8, C 50.1, B 133.8, M 115.5): pure colours, lit or
//                                half in shade, and what a tone curve makes of them. Measured on
//                                this city's right pictures (three's ACES, none or AgX): no pixel
//                                above 0.56 (orange roof tiles, hue 13°, untone-mapped); on the
//                                binary-colour mutant: a third to a half of the pixels.
//                                false_share_strict: max channel > 200, min < 40, hue within 15°
//                                of the same six (lit faces only; ACES desaturates many), for
//                                reference.
//   geometry_share               geometry pixels / all pixels
// Writes OUT_PREFIX.three.png (three's picture), .mask.png (the geometry pixels white, the ones
// left out as sky in ours grey), .side.png (ours | three | ΔE00 per pixel, black 0 to white ≥ 30,
// left-out pixels dark blue) and .json (the figures, the bounds, pass and problems); prints the
// JSON. Exit 0 when every bound given holds, 1 with a one-line reason otherwise, 2 on bad
// arguments. --self-test checks the ΔE00 code on Sharma, Wu and Dalal's (2005) published pairs.
import fs from 'node:fs';
import process from 'node:process';
import zlib from 'node:zlib';

function usage(message) {
  process.stderr.write(`lookalike-check: ${message}\nusage: lookalike-check.mjs REPORT VIEW OURS_PNG OUT_PREFIX ` +
    '[--max-false-share F] [--max-mean-de X] [--max-median-de Y] [--max-sky-in-ours S] | --self-test\n');
  process.exit(2);
}
function fail(message) {
  process.stderr.write(`lookalike-check: ${message}\n`);
  process.exit(1);
}

// ---- PNG: 8-bit grey, grey+alpha, RGB, RGBA, not interlaced; and an RGB encoder
function crc32(buf) {
  let c, crc = 0xffffffff;
  for (let n = 0; n < buf.length; ++n) {
    c = (crc ^ buf[n]) & 0xff;
    for (let k = 0; k < 8; ++k) c = c & 1 ? 0xedb88320 ^ (c >>> 1) : c >>> 1;
    crc = (crc >>> 8) ^ c;
  }
  return (crc ^ 0xffffffff) >>> 0;
}
function writePng(file, w, h, rgb) {
  const raw = Buffer.alloc((3 * w + 1) * h);
  for (let y = 0; y < h; ++y) {
    raw[y * (3 * w + 1)] = 0;
    rgb.copy ? rgb.copy(raw, y * (3 * w + 1) + 1, 3 * w * y, 3 * w * (y + 1))
      : raw.set(rgb.subarray(3 * w * y, 3 * w * (y + 1)), y * (3 * w + 1) + 1);
  }
  const chunk = (type, data) => {
    const out = Buffer.alloc(12 + data.length);
    out.writeUInt32BE(data.length, 0);
    out.write(type, 4, 'latin1');
    data.copy(out, 8);
    out.writeUInt32BE(crc32(out.subarray(4, 8 + data.length)), 8 + data.length);
    return out;
  };
  const ihdr = Buffer.alloc(13);
  ihdr.writeUInt32BE(w, 0);
  ihdr.writeUInt32BE(h, 4);
  ihdr.set([8, 2, 0, 0, 0], 8);
  fs.writeFileSync(file, Buffer.concat([Buffer.from([0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a]),
    chunk('IHDR', ihdr), chunk('IDAT', zlib.deflateSync(raw)), chunk('IEND', Buffer.alloc(0))]));
}
// -> {w, h, rgb: Uint8Array of w*h*3} (alpha dropped: both renderers write opaque pictures)
function readPng(buf, name) {
  if (buf.length < 8 || buf.readUInt32BE(0) !== 0x89504e47) throw new Error(`${name} is not a PNG`);
  let off = 8, w = 0, h = 0, depth = 0, type = 0, interlace = 0;
  const idat = [];
  while (off < buf.length) {
    const len = buf.readUInt32BE(off), kind = buf.toString('latin1', off + 4, off + 8);
    const data = buf.subarray(off + 8, off + 8 + len);
    if (kind === 'IHDR') [w, h, depth, type, interlace] = [data.readUInt32BE(0), data.readUInt32BE(4), data[8], data[9], data[12]];
    else if (kind === 'IDAT') idat.push(data);
    off += 12 + len;
  }
  const channels = { 0: 1, 2: 3, 4: 2, 6: 4 }[type];
  if (depth !== 8 || !channels || interlace) throw new Error(`${name}: PNG of depth ${depth}, type ${type}, interlace ${interlace} (this reader takes 8-bit grey, RGB, RGBA)`);
  const raw = zlib.inflateSync(Buffer.concat(idat));
  const stride = w * channels, px = new Uint8Array(stride * h);
  for (let y = 0; y < h; ++y) {
    const filter = raw[y * (stride + 1)], line = raw.subarray(y * (stride + 1) + 1, (y + 1) * (stride + 1));
    for (let x = 0; x < stride; ++x) {
      const a = x >= channels ? px[y * stride + x - channels] : 0, b = y ? px[(y - 1) * stride + x] : 0;
      const c = x >= channels && y ? px[(y - 1) * stride + x - channels] : 0;
      let p;
      if (filter === 0) p = 0;
      else if (filter === 1) p = a;
      else if (filter === 2) p = b;
      else if (filter === 3) p = (a + b) >> 1;
      else if (filter === 4) {
        const pa = Math.abs(b - c), pb = Math.abs(a - c), pc = Math.abs(a + b - 2 * c);
        p = pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
      } else throw new Error(`${name}: unknown PNG filter ${filter}`);
      px[y * stride + x] = (line[x] + p) & 0xff;
    }
  }
  const rgb = new Uint8Array(w * h * 3);
  for (let i = 0; i < w * h; ++i) {
    for (let k = 0; k < 3; ++k) rgb[3 * i + k] = px[i * channels + (channels < 3 ? 0 : k)];
  }
  return { w, h, rgb };
}
const dataUrlPng = (url, name) => {
  const m = /^data:image\/png;base64,(.*)$/s.exec(url ?? '');
  if (!m) throw new Error(`${name}: not a PNG data URL`);
  return Buffer.from(m[1], 'base64');
};

// ---- sRGB (8-bit, as written) -> CIELAB (D65, 2°), and CIEDE2000
const toLinear = new Float64Array(256).map((_, i) => {
  const c = i / 255;
  return c <= 0.04045 ? c / 12.92 : ((c + 0.055) / 1.055) ** 2.4;
});
function lab(r, g, b) {
  const R = toLinear[r], G = toLinear[g], B = toLinear[b];
  const X = (0.4124564 * R + 0.3575761 * G + 0.1804375 * B) / 0.95047;
  const Y = 0.2126729 * R + 0.7151522 * G + 0.0721750 * B;
  const Z = (0.0193339 * R + 0.1191920 * G + 0.9503041 * B) / 1.08883;
  const f = (t) => (t > 216 / 24389 ? Math.cbrt(t) : (24389 / 27 * t + 16) / 116);
  const fx = f(X), fy = f(Y), fz = f(Z);
  return [116 * fy - 16, 500 * (fx - fy), 200 * (fy - fz)];
}
const DEG = Math.PI / 180;
function deltaE00([L1, a1, b1], [L2, a2, b2]) {
  const C1 = Math.hypot(a1, b1), C2 = Math.hypot(a2, b2), Cb7 = ((C1 + C2) / 2) ** 7;
  const G = 0.5 * (1 - Math.sqrt(Cb7 / (Cb7 + 25 ** 7)));
  const ap1 = (1 + G) * a1, ap2 = (1 + G) * a2;
  const Cp1 = Math.hypot(ap1, b1), Cp2 = Math.hypot(ap2, b2);
  const hue = (b, a) => (a === 0 && b === 0 ? 0 : (Math.atan2(b, a) / DEG + 360) % 360);
  const hp1 = hue(b1, ap1), hp2 = hue(b2, ap2);
  const dL = L2 - L1, dC = Cp2 - Cp1;
  let dh = 0;
  if (Cp1 * Cp2 !== 0) {
    dh = hp2 - hp1;
    if (dh > 180) dh -= 360;
    else if (dh < -180) dh += 360;
  }
  const dH = 2 * Math.sqrt(Cp1 * Cp2) * Math.sin(dh / 2 * DEG);
  const Lb = (L1 + L2) / 2, Cb = (Cp1 + Cp2) / 2;
  let hb = hp1 + hp2;
  if (Cp1 * Cp2 !== 0) {
    if (Math.abs(hp1 - hp2) <= 180) hb /= 2;
    else hb = hb < 360 ? (hb + 360) / 2 : (hb - 360) / 2;
  }
  const T = 1 - 0.17 * Math.cos((hb - 30) * DEG) + 0.24 * Math.cos(2 * hb * DEG) + 0.32 * Math.cos((3 * hb + 6) * DEG) -
    0.20 * Math.cos((4 * hb - 63) * DEG);
  const dTheta = 30 * Math.exp(-(((hb - 275) / 25) ** 2));
  const Cb7p = Cb ** 7, RC = 2 * Math.sqrt(Cb7p / (Cb7p + 25 ** 7));
  const SL = 1 + 0.015 * (Lb - 50) ** 2 / Math.sqrt(20 + (Lb - 50) ** 2), SC = 1 + 0.045 * Cb, SH = 1 + 0.015 * Cb * T;
  const RT = -Math.sin(2 * dTheta * DEG) * RC;
  const l = dL / SL, c = dC / SC, hh = dH / SH;
  return Math.sqrt(l * l + c * c + hh * hh + RT * c * hh);
}

// False colours: see the header.
function hueOf(r, g, b) {
  const M = Math.max(r, g, b), m = Math.min(r, g, b), d = M - m;
  if (d === 0) return 0;
  let h = M === r ? (g - b) / d : M === g ? 2 + (b - r) / d : 4 + (r - g) / d;
  return (h * 60 + 360) % 360;
}
function nearPrimaryHue(r, g, b) {
  const h = hueOf(r, g, b);
  const off = Math.abs(((h + 30) % 60) - 30);   // distance to the nearest multiple of 60°
  return off <= 15;
}
// the CIELAB chroma of pure red, yellow, green, cyan, blue and magenta
const PURE_CHROMA = [[255, 0, 0], [255, 255, 0], [0, 255, 0], [0, 255, 255], [0, 0, 255], [255, 0, 255]]
  .map(([r, g, b]) => Math.hypot(...lab(r, g, b).slice(1)));
const isFalse = (r, g, b) => {
  if (!nearPrimaryHue(r, g, b)) return false;
  const [, A, B] = lab(r, g, b);
  return Math.hypot(A, B) >= 0.7 * PURE_CHROMA[Math.round(hueOf(r, g, b) / 60) % 6];
};
const isFalseStrict = (r, g, b) => Math.max(r, g, b) > 200 && Math.min(r, g, b) < 40 && nearPrimaryHue(r, g, b);

function selfTest() {
  // Sharma, Wu, Dalal (2005), table 1: pairs 1, 7, 14, 17, 20, 25, 34
  const pairs = [
    [[50, 2.6772, -79.7751], [50, 0, -82.7485], 2.0425],
    [[50, 0, 0], [50, -1, 2], 2.3669],
    [[50, 2.5, 0], [50, 0, -2.5], 4.3065],
    [[50, 2.5, 0], [73, 25, -18], 27.1492],
    [[50, 2.5, 0], [50, 3.1736, 0.5854], 1.0],
    [[60.2574, -34.0099, 36.2677], [60.4626, -34.1751, 39.4387], 1.2644],
    [[2.0776, 0.0795, -1.1350], [0.9033, -0.0636, -0.5514], 0.9082],
  ];
  for (const [p, r, want] of pairs) {
    const got = deltaE00(p, r), back = deltaE00(r, p);
    if (Math.abs(got - want) > 1e-4 || Math.abs(back - want) > 1e-4) fail(`self-test: ΔE00(${p}; ${r}) = ${got} / ${back}, published ${want}`);
  }
  const white = lab(255, 255, 255);
  if (Math.abs(white[0] - 100) > 1e-3 || Math.abs(white[1]) > 1e-2 || Math.abs(white[2]) > 1e-2) fail(`self-test: sRGB white is Lab ${white}`);
  if (!isFalse(255, 0, 255) || !isFalse(200, 20, 20) || !isFalse(0, 200, 200) || !isFalse(243, 28, 30) || isFalse(180, 80, 60) ||
    isFalse(255, 134, 99) || isFalse(200, 200, 200) || isFalse(100, 140, 60) || isFalse(90, 0, 0)) {
    fail('self-test: the false-colour rule misjudges a reference colour');
  }
  process.stdout.write(`lookalike-check: self-test ok (${pairs.length} published ΔE00 pairs, sRGB white, false colours)\n`);
}

function main() {
  const argv = process.argv.slice(2);
  if (argv[0] === '--self-test') return selfTest();
  const pos = [], bounds = {};
  for (let i = 0; i < argv.length; ++i) {
    const a = argv[i];
    const m = /^--max-(false-share|mean-de|median-de|sky-in-ours)$/.exec(a);
    if (m) {
      const v = Number(argv[++i]);
      if (!(v >= 0)) usage(`${a} wants a number ≥ 0`);
      bounds[m[1].replaceAll('-', '_')] = v;
    } else if (a.startsWith('--')) usage(`unknown option ${a}`);
    else pos.push(a);
  }
  if (pos.length !== 4) usage('REPORT VIEW OURS_PNG OUT_PREFIX are required');
  const [reportFile, view, oursFile, prefix] = pos;
  let report, three, ours, mask;
  try {
    report = JSON.parse(fs.readFileSync(reportFile, 'utf8'));
    const v = report.result?.views?.[view];
    if (!v) throw new Error(`${reportFile} has no view "${view}"${report.ok === false ? ' (the page failed)' : ''}`);
    const threePng = dataUrlPng(v.picture, `${view}.picture`);
    fs.writeFileSync(`${prefix}.three.png`, threePng);
    three = readPng(threePng, `${view}.picture`);
    mask = readPng(dataUrlPng(v.mask, `${view}.mask`), `${view}.mask`);
    ours = readPng(fs.readFileSync(oursFile), oursFile);
  } catch (e) {
    fail(String(e.message || e));
  }
  const { w, h } = ours;
  if (three.w !== w || three.h !== h || mask.w !== w || mask.h !== h) {
    fail(`${view}: our picture is ${w}x${h}, three's ${three.w}x${three.h} (mask ${mask.w}x${mask.h})`);
  }
  const n = w * h;
  const drawn = new Uint8Array(n);
  for (let i = 0; i < n; ++i) drawn[i] = mask.rgb[3 * i] > 127 ? 1 : 0;
  const all = (i, want) => {   // pixel i and its 8 neighbours all `want` (outside the frame counts as agreeing)
    const x = i % w, y = (i - x) / w;
    for (let dy = -1; dy <= 1; ++dy) {
      for (let dx = -1; dx <= 1; ++dx) {
        const X = x + dx, Y = y + dy;
        if (X >= 0 && Y >= 0 && X < w && Y < h && drawn[Y * w + X] !== want) return false;
      }
    }
    return true;
  };
  const labOf = (img, i) => lab(img.rgb[3 * i], img.rgb[3 * i + 1], img.rgb[3 * i + 2]);
  // our sky's colour per row
  const skyRow = new Array(h).fill(null);
  for (let y = 0; y < h; ++y) {
    const ch = [[], [], []];
    for (let x = 0; x < w; ++x) {
      const i = y * w + x;
      if (!drawn[i] && all(i, 0)) for (let k = 0; k < 3; ++k) ch[k].push(ours.rgb[3 * i + k]);
    }
    if (ch[0].length >= 8) {
      const med = (a) => a.sort((p, q) => p - q)[a.length >> 1];
      skyRow[y] = lab(med(ch[0]), med(ch[1]), med(ch[2]));
    }
  }
  // the geometry pixels
  const des = [], keep = new Uint8Array(n);   // keep: 1 geometry, 2 sky in ours, 0 neither
  let skyInOurs = 0, candidates = 0, dL = 0, falseN = 0, falseStrictN = 0;
  const deMap = new Float32Array(n);
  for (let i = 0; i < n; ++i) {
    if (!drawn[i] || !all(i, 1)) continue;
    ++candidates;
    const o = labOf(ours, i), y = Math.floor(i / w);
    if (skyRow[y] && deltaE00(o, skyRow[y]) < 2) {
      keep[i] = 2;
      ++skyInOurs;
      continue;
    }
    keep[i] = 1;
    const t = labOf(three, i), d = deltaE00(o, t);
    des.push(d);
    deMap[i] = d;
    dL += t[0] - o[0];
    const [r, g, b] = [three.rgb[3 * i], three.rgb[3 * i + 1], three.rgb[3 * i + 2]];
    if (isFalse(r, g, b)) ++falseN;
    if (isFalseStrict(r, g, b)) ++falseStrictN;
  }
  if (!des.length) fail(`${view}: no pixel shows geometry in both pictures`);
  des.sort((p, q) => p - q);
  const q = (f) => des[Math.min(des.length - 1, Math.floor(f * des.length))];
  const r3 = (x) => Number(x.toFixed(3)), r5 = (x) => Number(x.toFixed(5));
  const figures = {
    view, size: [w, h], geometry_share: r3(des.length / n), sky_in_ours: r5(candidates ? skyInOurs / candidates : 0),
    de_mean: r3(des.reduce((s, x) => s + x, 0) / des.length), de_median: r3(q(0.5)), de_p90: r3(q(0.9)),
    dL_mean: r3(dL / des.length), false_share: r5(falseN / des.length), false_share_strict: r5(falseStrictN / des.length),
    three: { glb: report.result.glb, tone: report.result.tone, lod: report.result.lod, exposure: report.result.views[view].exposure,
      materials: report.result.gltf.materials.length, textures: report.result.gltf.textures, vertex_colours: report.result.gltf.vertex_colours },
  };
  // the pictures
  const maskOut = new Uint8Array(3 * n), side = new Uint8Array(3 * 3 * n);
  for (let y = 0; y < h; ++y) {
    for (let x = 0; x < w; ++x) {
      const i = y * w + x, s = 3 * (y * 3 * w + x);
      maskOut.fill(keep[i] === 1 ? 255 : keep[i] === 2 ? 128 : 0, 3 * i, 3 * i + 3);
      for (let k = 0; k < 3; ++k) {
        side[s + k] = ours.rgb[3 * i + k];
        side[s + 3 * w + k] = three.rgb[3 * i + k];
      }
      const v = keep[i] === 1 ? Math.min(255, Math.round(deMap[i] / 30 * 255)) : -1;
      side.set(v < 0 ? [16, 24, 64] : [v, v, v], s + 6 * w);
    }
  }
  writePng(`${prefix}.mask.png`, w, h, maskOut);
  writePng(`${prefix}.side.png`, 3 * w, h, side);

  const problems = [];
  const over = (key, value, label) => {
    if (bounds[key] !== undefined && !(value <= bounds[key])) problems.push(`${label} ${value} > ${bounds[key]}`);
  };
  over('false_share', figures.false_share, 'false-colour share');
  over('mean_de', figures.de_mean, 'mean ΔE00');
  over('median_de', figures.de_median, 'median ΔE00');
  over('sky_in_ours', figures.sky_in_ours, 'share of three\'s geometry that is sky in ours');
  const out = { ...figures, bounds, pass: problems.length === 0, problems };
  fs.writeFileSync(`${prefix}.json`, `${JSON.stringify(out, null, 1)}\n`);
  process.stdout.write(`${JSON.stringify(out)}\n`);
  if (problems.length) fail(`${view}: ${problems.join('; ')}`);
}

main();
