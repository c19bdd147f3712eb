// The bottom panel's two lists: the problems that can still occur under your decisions (the
// model's and launch files' diagnostics, and the HAROS project's rules), and your decisions, in
// the order you made them, each undoable on its own.
import { el } from './format';
import type { Page } from './page';
import { statusOf } from './model';
import type { Problem } from './types';
import { locLink, redraw } from './ui';

const PROBLEMS_SHOWN = 200;

// a forced redraw waiting for a release stays forced when an unforced one replaces it
let forced = false;

export function renderProblems(page: Page, force = true): void {
  forced = forced || force;
  redraw('problems', () => {
    const f = forced;
    forced = false;
    drawProblems(page, f);
  });
}

function drawProblems(page: Page, force: boolean): void {
  const box = document.getElementById('problems') as HTMLElement | null;
  if (!box) {
    return;
  }
  // a click that changes no problem's status does not redraw the list (hundreds on big models)
  const key = JSON.stringify([page.model.model, page.problems?.length ?? -1, page.problemStatus, page.showRuledOut,
    page.showAllProblems]);
  if (!force && key === box.dataset.drawn) {
    return;
  }
  box.dataset.drawn = key;
  const tab = document.getElementById('tab-problems');
  if (page.problems === null) {
    if (tab) tab.textContent = 'Problems …';
    box.replaceChildren(el('div', { class: 'panel-head' },
      el('span', { class: 'muted', id: 'problem-count', 'data-checking': 'true' }, 'checking the model and its launch files…')));
    return;
  }
  const shown: Problem[] = [];
  const ruledOut: Problem[] = [];
  for (const p of page.problems) {
    const st = page.problemStatus[p.id] ?? 'certain';
    (st === 'excluded' ? ruledOut : shown).push(p);
  }
  if (tab) tab.textContent = `Problems (${shown.length})`;
  const list = el('ul', { class: 'problem-list' });
  const item = (p: Problem, out: boolean) => {
    const st = page.problemStatus[p.id];
    const rule = p.code.startsWith('haros-rule');
    const li = el('li', { class: `problem sev-${p.severity}${out ? ' ruled-out' : ''}${rule ? ' rule' : ''}`, 'data-code': p.code,
      'data-status': st },
    el('span', { class: `sev sev-${p.severity}`, title: p.severity }, p.severity[0].toUpperCase()),
    el('span', { class: 'code' }, rule ? (p.code === 'haros-rule' ? 'HAROS rule' : 'rule not evaluated') : p.code),
    el('span', { class: 'msg' }, p.message),
    p.location ? locLink(p.location) : null,
    st === 'possible' ? el('span', { class: 'tag', title: p.condition ? `when ${p.condition}` : 'in some products' }, 'in some products') : null,
    out ? el('span', { class: 'tag' }, 'ruled out by your decisions') : null,
    );
    list.append(li);
  };
  const listed = [...shown.map((p) => [p, false] as const), ...(page.showRuledOut ? ruledOut.map((p) => [p, true] as const) : [])];
  const limit = page.showAllProblems ? listed.length : PROBLEMS_SHOWN;
  listed.slice(0, limit).forEach(([p, out]) => item(p, out));
  if (listed.length > limit) {
    const more = el('button', { class: 'more-problems' }, `show all ${listed.length}`);
    more.addEventListener('click', () => {
      page.showAllProblems = true;
      renderProblems(page);
    });
    list.append(el('li', { class: 'problem' }, more));
  }
  const toggle = el('label', { class: 'toggle' });
  const cb = el('input', { type: 'checkbox', id: 'show-ruled-out' }) as HTMLInputElement;
  cb.checked = page.showRuledOut;
  cb.addEventListener('change', () => {
    page.showRuledOut = cb.checked;
    renderProblems(page);
  });
  toggle.append(cb, ` show ${ruledOut.length} ruled out`);
  box.replaceChildren(
    el('div', { class: 'panel-head' },
      el('span', { id: 'problem-count', 'data-shown': String(shown.length), 'data-ruled-out': String(ruledOut.length) },
        `${shown.length} can still occur` + (ruledOut.length ? `, ${ruledOut.length} ruled out by your decisions` : '')),
      ruledOut.length ? toggle : null),
    shown.length || page.showRuledOut ? list : el('div', { class: 'muted empty-problems' }, 'No problem can occur in the remaining products.'),
  );
}

export function renderDecisions(page: Page): void {
  redraw('decisions', () => drawDecisions(page));
}

function drawDecisions(page: Page): void {
  const box = document.getElementById('decisions') as HTMLElement | null;
  if (!box) {
    return;
  }
  const s = page.state;
  const entries = Object.entries(s.decisions);
  // an answer that changes nothing here (counts, the problems, a refusal) leaves the list, its
  // buttons and the focus alone
  const key = JSON.stringify([page.model.model, entries, Object.keys(s.implied).length, s.open.length, s.complete,
    page.history.length > 0]);
  if (box.dataset.drawn === key) {
    return;
  }
  box.dataset.drawn = key;
  const tab = document.getElementById('tab-decisions');
  if (tab) tab.textContent = `Decisions (${entries.length})`;
  const undoLast = el('button', { class: 'small', id: 'undo-last', title: 'go back to the decisions before the last change' }, 'Undo last');
  (undoLast as HTMLButtonElement).disabled = !page.history.length;
  undoLast.addEventListener('click', () => {
    const prev = page.history.pop();
    if (prev) {
      // 'undo' does not push onto the history
      void page.setDecisions(prev, 'undo').then((ok) => {
        if (!ok) {
          page.history.push(prev);
          renderDecisions(page);
        }
      });
    }
  });
  const resetAll = el('button', { class: 'small', title: 'forget every decision' }, 'Undo all');
  (resetAll as HTMLButtonElement).disabled = !entries.length;
  resetAll.addEventListener('click', () => void page.setDecisions({}, 'reset'));
  const implied = Object.keys(s.implied).length;
  const head = el('div', { class: 'panel-head' },
    el('span', { id: 'decision-count', 'data-count': String(entries.length) },
      `${entries.length} decision${entries.length === 1 ? '' : 's'} · ${implied} implied · ${s.open.length} open`
      + (s.complete ? ' · every feature decided' : '')),
    undoLast, resetAll);
  if (!entries.length) {
    box.replaceChildren(head, el('div', { class: 'muted empty-problems' },
      'No decision yet: include (+, ✓) or exclude (−, ✕) features; each one appears here, undoable on its own.'));
    return;
  }
  const ul = el('ul', { class: 'decision-list' });
  entries.forEach(([name, v], i) => {
    const f = page.index.byId.get(name);
    const undo = el('button', { class: 'small undo', title: `forget: ${v ? 'include' : 'exclude'} ${name}`, 'data-feature': name }, 'Undo');
    undo.addEventListener('click', () => void page.decide(name, null));
    const link = el('a', { href: '#', class: 'feature-link', 'data-feature': name, title: f?.longName ?? name }, name);
    link.addEventListener('click', (ev) => {
      ev.preventDefault();
      page.revealFeature(name);
    });
    ul.append(el('li', { class: `decision st-${statusOf(s, name)}`, 'data-feature': name },
      el('span', { class: 'n muted' }, `${i + 1}.`),
      el('span', { class: `mark ${v ? 'in' : 'out'}` }, v ? '✓' : '✕'),
      el('span', {}, v ? 'include ' : 'exclude ', link),
      undo));
  });
  box.replaceChildren(head, ul);
}
