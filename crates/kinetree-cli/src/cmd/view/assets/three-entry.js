export * from 'three';
export { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';
export { TransformControls } from 'three/examples/jsm/controls/TransformControls.js';
export { STLLoader } from 'three/examples/jsm/loaders/STLLoader.js';
export { OBJLoader } from 'three/examples/jsm/loaders/OBJLoader.js';
export { ColladaLoader } from 'three/examples/jsm/loaders/ColladaLoader.js';
export { PLYLoader } from 'three/examples/jsm/loaders/PLYLoader.js';
export { CSS2DRenderer, CSS2DObject } from 'three/examples/jsm/renderers/CSS2DRenderer.js';
