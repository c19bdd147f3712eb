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
