// The JSON the configurator API answers (tvl_lsp/configurator/api.py).

export interface Location {
  path: string;
  line: number; // 0-based
  col: number;
  endLine: number;
  endCol: number;
}

export interface Group {
  kind: string; // oneOf | someOf | allOf | card
  lo: number;
  hi: number | null;
  text: string;
  kinds?: string[]; // every group kind of the feature (a UVL feature may have several groups)
}

export interface FeatureNode {
  id: string;
  name: string;
  longName: string;
  optional: boolean;
  /** in its parent's group: root | mandatory | optional | member */
  kind?: string;
  /** the kind in words true to the model ("group member: alternative, exactly one of 3") */
  kindText?: string;
  ref?: boolean; // a `shared` reference to a feature declared elsewhere
  location: Location | null;
  group?: Group;
  constraints?: string[];
  children: FeatureNode[];
}

export interface GraphElement {
  id: string;
  kind: 'node' | 'topic' | 'param' | 'service' | string;
  name: string;
  label: string;
  condition: string | null;
  location: Location | null;
  details: Record<string, unknown>;
}

export interface GraphEdge {
  id: string;
  source: string;
  target: string;
  kind: string;
  condition: string | null;
  location: Location | null;
}

export interface NoTopics {
  types: string[];
  sourcesHere: string[];
  sourcesAway: string[];
  projectFiles: string[];
}

export interface GraphJson {
  elements: GraphElement[];
  edges: GraphEdge[];
  source: string;
  status?: Record<string, Status>;
  notes?: string[];
  /** set when the graph has nodes but no topic or service: what would add them */
  noTopics?: NoTopics;
}

export interface Related {
  message: string;
  location: Location | null;
}

export interface Problem {
  id: string;
  code: string;
  severity: 'error' | 'warning' | 'information' | 'hint';
  message: string;
  location: Location | null;
  related: Related[];
  condition: string | null;
  witness: Record<string, boolean> | null;
}

export type Status = 'certain' | 'possible' | 'absent' | 'excluded';

export interface State {
  decisions: Record<string, boolean>;
  implied: Record<string, boolean>;
  open: string[];
  complete: boolean;
  problems: Record<string, Status> | null; // null: the files are not checked yet
  graph: Record<string, Status> | null; // null: the graph is not built yet
  /** the model has no product at all */
  void?: boolean;
}

export interface ProblemsJson {
  problems: Problem[];
  status: Record<string, Status> | null;
}

export interface ModelJson {
  model: string;
  name: string;
  roots: string[];
  launch: string | null;
  launches: string[];
  features: number;
  tree: FeatureNode;
  state: State;
}

export interface Refusal {
  feature: string;
  value: boolean;
  conflictsWith: Record<string, boolean>;
  because: { label: string; location: Location | null }[];
  message: string;
}

export interface DecideResult {
  ok: boolean;
  state: State;
  refused?: Refusal;
  /** the counts of the features asked for, when the model is compiled */
  counts?: Counts;
}

export interface Counts {
  total: string | null;
  remaining: string | null;
  features: Record<string, string>;
  complete: boolean;
  decisions: Record<string, boolean>;
  /** true while the model is being compiled in the background (no counts yet: ask again) */
  pending?: boolean;
  /** ready | compiling | failed | unusable: where the model's compilation stands */
  status?: string;
  message?: string;
  seconds?: number;
  /** d4 | pyganak | trivial: which engine counted */
  engine?: string | null;
  /** seconds d4 may compile the model */
  budget?: number;
}

export interface Targets {
  roots: string[];
  models: { model: string; launches: string[] }[];
  initial: string | null;
}

export interface GenerateResult {
  files: { path: string; relative: string; text: string }[];
  written?: string[];
  folder: string;
  mode: string;
  products?: number;
  limit?: number;
  cut?: boolean;
  available?: number | null;
}

export interface Explanation {
  feature: string;
  value: boolean | null;
  implied: boolean;
  byDecisions: Record<string, boolean>;
  because: { label: string; location: Location | null }[];
  text: string;
}

export interface ConfigFile {
  path: string;
  name: string;
  relative: string;
  format: string;
  mtime: number;
}

export interface ConfigsJson {
  folder: string;
  relative: string;
  formats: string[];
  files: ConfigFile[];
}

export interface SaveResult {
  path: string;
  relative: string;
  text: string;
  format: string;
  written?: string[];
}

export interface LoadResult extends DecideResult {
  loaded: { format: string; unknown: string[]; unknownCount: number; ignored: string[]; path: string; decisions: number };
}

export interface CompleteResult extends DecideResult {
  added: Record<string, boolean>;
  how: string;
  engine: string;
}

export interface LaunchCandidate {
  path: string;
  relative: string;
  args: number;
  matches: number;
}

export interface LaunchesJson {
  launch: string | null;
  candidates: LaunchCandidate[];
}

export interface Excerpt {
  path: string;
  relative: string;
  start: number;
  line: number;
  lines: string[];
}
