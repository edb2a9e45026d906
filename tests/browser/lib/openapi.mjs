// server/openapi.yaml as a checker of real answers: finds the operation a request names (method
// and path against the document's path templates), the response the document declares for the
// answer's status (the status, else its class such as 4XX, else default) and the media type of
// the answer's Content-Type, and validates a JSON body against that response's schema with ajv.
//
// The document is OpenAPI 3.0.3, whose Schema Object is a subset of JSON Schema draft 7 plus
// `nullable` (which ajv reads as OpenAPI defines it: null is allowed where the schema has a type)
// and `format: binary`. So ajv's default draft-07 dialect applies, in strict mode: a keyword that
// is not JSON Schema (a typo, or an OpenAPI 3.1 keyword) fails the compilation. `$ref`s to
// #/components/schemas/NAME become references into one schema that holds every component.
import { readFileSync } from 'node:fs';
import Ajv from 'ajv';
import yaml from 'js-yaml';

const COMPONENT_REF = /^#\/components\/schemas\/([^/]+)$/;
const ROOT_ID = 'openapi-components';

// A deep copy of a schema with its component references made absolute (into ROOT_ID).
function absoluteRefs(schema) {
  if (Array.isArray(schema)) return schema.map(absoluteRefs);
  if (schema === null || typeof schema !== 'object') return schema;
  const out = {};
  for (const [k, v] of Object.entries(schema)) {
    if (k === '$ref') {
      const m = COMPONENT_REF.exec(v);
      if (!m) throw new Error(`a schema $ref outside #/components/schemas: ${v}`);
      out.$ref = `${ROOT_ID}#/definitions/${m[1]}`;
    } else {
      out[k] = absoluteRefs(v);
    }
  }
  return out;
}

// The media type of a Content-Type value, lower case, without parameters.
export const mediaType = (contentType) => (contentType || '').split(';')[0].trim().toLowerCase();

export class OpenApi {
  constructor(file) {
    this.doc = yaml.load(readFileSync(file, 'utf8'));
    if (this.doc.openapi !== '3.0.3') throw new Error(`expected OpenAPI 3.0.3, the document says ${this.doc.openapi}`);
    this.ajv = new Ajv({ allErrors: true, strict: true, strictTypes: false, strictTuples: false, strictRequired: false });
    this.ajv.addFormat('binary', true);
    const definitions = {};
    for (const [name, s] of Object.entries(this.doc.components.schemas)) definitions[name] = absoluteRefs(s);
    this.ajv.addSchema({ $id: ROOT_ID, definitions });
    this.compiled = new Map();
    this.base = new URL(this.doc.servers[0].url, 'http://x').pathname.replace(/\/$/, '');
    // Path templates as regular expressions, literal ones before templated ones (so that
    // /sweeps/estimate is not read as /sweeps/{id}).
    this.templates = Object.keys(this.doc.paths)
      .map((t) => ({ t, re: new RegExp(`^${t.replace(/\{[^}]+\}/g, '[^/]+')}$`), params: (t.match(/\{/g) || []).length }))
      .sort((a, b) => a.params - b.params);
    this.seen = new Set(); // operationIds of the answers checked
  }

  // Every operation of the document: [{ id, method, path }].
  operations() {
    const out = [];
    for (const [path, item] of Object.entries(this.doc.paths)) {
      for (const method of ['get', 'put', 'post', 'delete', 'patch', 'head', 'options']) {
        if (item[method]) out.push({ id: item[method].operationId, method: method.toUpperCase(), path });
      }
    }
    return out;
  }

  // The operation of a request: `path` is the URL's path as sent (with the servers' /api/v1).
  operation(method, path) {
    if (!path.startsWith(`${this.base}/`)) throw new Error(`${path} is not below the document's server URL ${this.base}`);
    const rel = path.slice(this.base.length);
    for (const { t, re } of this.templates) {
      const op = re.test(rel) && this.doc.paths[t][method.toLowerCase()];
      if (op) return { template: t, op };
    }
    throw new Error(`the document has no operation ${method} ${rel}`);
  }

  // A component reference resolved (responses), or the object itself.
  resolve(obj) {
    if (!obj || !obj.$ref) return obj;
    const parts = obj.$ref.replace(/^#\//, '').split('/');
    let node = this.doc;
    for (const p of parts) node = node?.[p];
    if (!node) throw new Error(`unresolved $ref ${obj.$ref}`);
    return node;
  }

  validator(schema) {
    let v = this.compiled.get(schema);
    if (!v) {
      v = this.ajv.compile(absoluteRefs(schema));
      this.compiled.set(schema, v);
    }
    return v;
  }

  // Compiles every schema of every response and request body (a schema ajv refuses throws).
  compileAll() {
    let n = 0;
    for (const { method, path } of this.operations()) {
      const op = this.doc.paths[path][method.toLowerCase()];
      const bodies = [op.requestBody, ...Object.values(op.responses)].map((r) => this.resolve(r));
      for (const r of bodies) {
        for (const media of Object.values(r?.content || {})) {
          if (media.schema) { this.validator(media.schema); n++; }
        }
      }
    }
    return n;
  }

  // Problems of a JSON value against a schema, as text ('' when it conforms).
  problems(schema, value) {
    const v = this.validator(schema);
    if (v(value)) return '';
    return this.ajv.errorsText(v.errors, { separator: '\n  ', dataVar: 'body' });
  }

  // Checks a request body the test sends against the operation's request schema (JSON only).
  checkRequest(method, path, body) {
    const { template, op } = this.operation(method, path);
    const media = this.resolve(op.requestBody)?.content?.['application/json'];
    if (!media) throw new Error(`${method} ${template} declares no JSON request body`);
    const p = this.problems(media.schema, body);
    if (p) throw new Error(`the request body of ${method} ${template} does not match its schema:\n  ${p}`);
  }

  // Checks an answer: { method, path, status, contentType, text }. Returns the key of the
  // response that describes it ('200', '4XX', 'default'). Throws with the reason otherwise.
  checkAnswer({ method, path, status, contentType, text }) {
    const { template, op } = this.operation(method, path);
    const where = `${method} ${template} -> ${status}`;
    const key = [String(status), `${String(status)[0]}XX`, 'default'].find((k) => op.responses[k]);
    if (!key) throw new Error(`${where}: the document declares no response for it`);
    if (status < 400 && key !== String(status)) throw new Error(`${where}: a success must be declared by its own status, not ${key}`);
    this.seen.add(op.operationId);
    const response = this.resolve(op.responses[key]);
    const content = response.content || {};
    if (Object.keys(content).length === 0) {
      if (text !== '') throw new Error(`${where}: the document declares no body, the answer has ${text.length} bytes`);
      return key;
    }
    const type = mediaType(contentType);
    const media = content[type];
    if (!media) throw new Error(`${where}: Content-Type ${type} is not among the declared ${Object.keys(content).join(', ')}`);
    if (!media.schema) throw new Error(`${where}: ${type} has no schema`);
    if (type === 'application/json') {
      let value;
      try { value = JSON.parse(text); } catch (e) { throw new Error(`${where}: not JSON: ${e.message}`); }
      const p = this.problems(media.schema, value);
      if (p) throw new Error(`${where}: the body does not match its schema:\n  ${p}`);
    } else if (media.schema.type !== 'string') {
      throw new Error(`${where}: ${type} is not JSON, but its schema is not a string`);
    }
    return key;
  }
}
