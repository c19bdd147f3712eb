// Exact counts arrive as decimal strings (they exceed 2^53); show them readably.

/** "1,234" for small counts, "4.42 × 10^97" for big ones (the exact value goes in a tooltip). */
export function formatCount(s: string | null | undefined): string {
  if (s === null || s === undefined) {
    return '…';
  }
  if (!/^\d+$/.test(s)) {
    return s;
  }
  if (s.length <= 12) {
    return Number(s).toLocaleString('en-US');
  }
  const mant = `${s[0]}.${s.slice(1, 3)}`;
  return `${mant} × 10${superscript(String(s.length - 1))}`;
}

const SUP: Record<string, string> = {
  '0': '⁰', '1': '¹', '2': '²', '3': '³', '4': '⁴', '5': '⁵', '6': '⁶', '7': '⁷', '8': '⁸', '9': '⁹',
};

function superscript(n: string): string {
  return n.split('').map((c) => SUP[c] ?? c).join('');
}

/** share of `part` in `whole` (both decimal strings) as a percentage text. */
export function percent(part: string, whole: string): string {
  if (whole === '0') {
    return '0 %';
  }
  // BigInt keeps it exact for any size
  const p = (BigInt(part) * 10000n) / BigInt(whole);
  const v = Number(p) / 100;
  if (v === 0 && part !== '0') {
    return '<0.01 %';
  }
  return `${v >= 10 || Number.isInteger(v) ? v.toFixed(0) : v.toFixed(1)} %`;
}

export function basename(p: string): string {
  const i = Math.max(p.lastIndexOf('/'), p.lastIndexOf('\\'));
  return i >= 0 ? p.slice(i + 1) : p;
}

export function el<K extends keyof HTMLElementTagNameMap>(
  tag: K,
  attrs: Record<string, string> = {},
  ...children: (Node | string | null | undefined)[]
): HTMLElementTagNameMap[K] {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (k === 'class') {
      e.className = v;
    } else {
      e.setAttribute(k, v);
    }
  }
  for (const c of children) {
    if (c !== null && c !== undefined) {
      e.append(c);
    }
  }
  return e;
}

/** The exact count with thin groups of three digits (for "exact digits on demand"). */
export function exactCount(s: string): string {
  return s.replace(/\B(?=(\d{3})+(?!\d))/g, ',');
}

let canvas: HTMLCanvasElement | null = null;

/** The width of `text` in `font` (a CSS font shorthand), in pixels. */
export function textWidth(text: string, font: string): number {
  canvas = canvas ?? document.createElement('canvas');
  const ctx = canvas.getContext('2d');
  if (!ctx) {
    return text.length * 7;
  }
  ctx.font = font;
  return ctx.measureText(text).width;
}

/** `text` shortened in the middle ("N_1003…F_100311") to fit `width` pixels in `font`: the
 * start and the end of a name are what tell features apart. */
const fitted = new Map<string, string>();

export function middleEllipsis(text: string, width: number, font: string): string {
  const key = `${font}|${Math.round(width)}|${text}`;
  let got = fitted.get(key);
  if (got === undefined) {
    got = middle(text, width, font);
    if (fitted.size > 20000) {
      fitted.clear();
    }
    fitted.set(key, got);
  }
  return got;
}

function middle(text: string, width: number, font: string): string {
  if (textWidth(text, font) <= width) {
    return text;
  }
  let lo = 1;
  let hi = text.length - 1;
  let best = text[0] + '…';
  while (lo <= hi) {
    const keep = Math.floor((lo + hi) / 2);
    const head = Math.ceil(keep / 2);
    const cand = text.slice(0, head) + '…' + text.slice(text.length - (keep - head));
    if (textWidth(cand, font) <= width) {
      best = cand;
      lo = keep + 1;
    } else {
      hi = keep - 1;
    }
  }
  return best;
}

/** `text` cut at the end to fit `width` pixels. */
export function endEllipsis(text: string, width: number, font: string): string {
  if (textWidth(text, font) <= width) {
    return text;
  }
  let lo = 0;
  let hi = text.length;
  while (lo < hi) {
    const mid = Math.ceil((lo + hi) / 2);
    if (textWidth(text.slice(0, mid) + '…', font) <= width) {
      lo = mid;
    } else {
      hi = mid - 1;
    }
  }
  return text.slice(0, lo) + '…';
}

/** The names a presence condition mentions ("Random && !Teleop" -> Random, Teleop). */
export function conditionNames(cond: string | null | undefined): string[] {
  if (!cond) {
    return [];
  }
  const out = new Set<string>();
  for (const m of cond.matchAll(/[A-Za-z_][\w.]*/g)) {
    if (m[0] !== 'true' && m[0] !== 'false') {
      out.add(m[0]);
    }
  }
  return [...out];
}

/** "in 1,204 of 2,304 remaining (52 %)" */
export function countPhrase(n: string | undefined, remaining: string | null | undefined): string {
  if (n === undefined || remaining === null || remaining === undefined) {
    return '';
  }
  return `in ${formatCount(n)} of ${formatCount(remaining)} remaining (${percent(n, remaining)})`;
}
