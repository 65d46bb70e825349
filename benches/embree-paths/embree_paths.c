// Embree 3 on the rays Penumbra's path tracer traces (dumped by raydump.patch): the
// closest-hit and the shadow rays, first one by one in the order the path tracer traces
// them (rtcIntersect1/rtcOccluded1), then sorted into wavefront order (by depth, then path)
// and traced in packets of 16 (rtcIntersect16/rtcOccluded16), as Mitsuba 3's LLVM
// variants do. Usage: embree_paths MESH.ply RAYDUMP.bin (see run.sh).
#include <embree3/rtcore.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>
#include <time.h>
#include <stdint.h>
static void die(const char *m) { fprintf(stderr, "embree_paths: %s\n", m); exit(2); }
typedef struct { uint32_t id, depth, kind; float r[7]; } Rec;
static double now(void) { struct timespec t; clock_gettime(CLOCK_MONOTONIC, &t); return t.tv_sec + 1e-9 * t.tv_nsec; }
static int bydepth(const void *a, const void *b) { const Rec *x = a, *y = b;
  if (x->depth != y->depth) return x->depth < y->depth ? -1 : 1; return x->id < y->id ? -1 : x->id > y->id; }
static void read_ply(const char *path, float **V, size_t *nv, unsigned **F, size_t *nf) {
  FILE *f = fopen(path, "rb");
  if (!f) die("cannot open mesh");
  char line[512];
  size_t vprops = 0;
  int in_vertex = 0;
  *nv = *nf = 0;
  while (fgets(line, sizeof line, f)) {
    if (!strncmp(line, "element vertex", 14)) { *nv = strtoull(line + 14, 0, 10); in_vertex = 1; }
    else if (!strncmp(line, "element face", 12)) { *nf = strtoull(line + 12, 0, 10); in_vertex = 0; }
    else if (!strncmp(line, "property float", 14) && in_vertex) vprops++;
    else if (!strncmp(line, "end_header", 10)) break;
  }
  if (!*nv || !*nf || vprops < 3) die("unsupported PLY header");
  float *raw = malloc(*nv * vprops * sizeof(float));
  if (fread(raw, sizeof(float) * vprops, *nv, f) != *nv) die("short vertex data");
  *V = malloc(*nv * 3 * sizeof(float));
  for (size_t i = 0; i < *nv; i++) memcpy(*V + 3 * i, raw + vprops * i, 3 * sizeof(float));
  free(raw);
  *F = malloc(*nf * 3 * sizeof(unsigned));
  for (size_t i = 0; i < *nf; i++) {
    unsigned char n;
    if (fread(&n, 1, 1, f) != 1 || n != 3) die("non-triangle face");
    if (fread(*F + 3 * i, sizeof(unsigned), 3, f) != 3) die("short face data");
  }
  fclose(f);
}

int main(int argc, char **argv) {
  if (argc != 3) die("usage: embree_paths MESH.ply RAYDUMP.bin");
  FILE *f = fopen(argv[2], "rb");
  if (!f) die("cannot open the ray dump"); fseek(f, 0, SEEK_END); size_t n = ftell(f) / sizeof(Rec); fseek(f, 0, SEEK_SET);
  Rec *all = malloc(n * sizeof(Rec)); if (fread(all, sizeof(Rec), n, f) != n) die("short ray dump"); fclose(f);
  float *V; unsigned *F; size_t nv, nf; read_ply(argv[1], &V, &nv, &F, &nf);
  RTCDevice dev = rtcNewDevice("threads=1"); RTCScene scene = rtcNewScene(dev);
  rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
  RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
  float *vb = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 12, nv);
  unsigned *ib = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 12, nf);
  memcpy(vb, V, nv * 12); memcpy(ib, F, nf * 12); rtcCommitGeometry(g); rtcAttachGeometry(scene, g); rtcCommitScene(scene);
  Rec *c = malloc(n * sizeof(Rec)), *s = malloc(n * sizeof(Rec)); size_t nc = 0, ns = 0;
  for (size_t i = 0; i < n; i++) { if (all[i].kind == 0) c[nc++] = all[i]; else s[ns++] = all[i]; }
  struct RTCIntersectContext ctx; rtcInitIntersectContext(&ctx);
  for (int pass = 0; pass < 2; pass++) {
    if (pass == 1) { qsort(c, nc, sizeof(Rec), bydepth); qsort(s, ns, sizeof(Rec), bydepth); }
    for (int rep = 0; rep < 3; rep++) {
      double t0 = now(); size_t hits = 0;
      if (pass == 0) {
        for (size_t i = 0; i < nc; i++) { struct RTCRayHit rh; float *r = c[i].r;
          rh.ray.org_x = r[0]; rh.ray.org_y = r[1]; rh.ray.org_z = r[2]; rh.ray.dir_x = r[3]; rh.ray.dir_y = r[4]; rh.ray.dir_z = r[5];
          rh.ray.tnear = 0; rh.ray.tfar = INFINITY; rh.ray.mask = -1; rh.ray.flags = 0; rh.ray.time = 0; rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
          rtcIntersect1(scene, &ctx, &rh); hits += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID; }
      } else {
        for (size_t i = 0; i < nc; i += 16) { struct RTCRayHit16 rh __attribute__((aligned(64))); int valid[16] __attribute__((aligned(64)));
          for (int k = 0; k < 16; k++) { size_t q = i + k < nc ? i + k : nc - 1; float *r = c[q].r; valid[k] = i + k < nc ? -1 : 0;
            rh.ray.org_x[k] = r[0]; rh.ray.org_y[k] = r[1]; rh.ray.org_z[k] = r[2]; rh.ray.dir_x[k] = r[3]; rh.ray.dir_y[k] = r[4]; rh.ray.dir_z[k] = r[5];
            rh.ray.tnear[k] = 0; rh.ray.tfar[k] = INFINITY; rh.ray.mask[k] = -1; rh.ray.flags[k] = 0; rh.ray.time[k] = 0; rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID; }
          rtcIntersect16(valid, scene, &ctx, &rh);
          for (int k = 0; k < 16 && i + k < nc; k++) hits += rh.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID; }
      }
      double t1 = now(); size_t blocked = 0;
      if (pass == 0) {
        for (size_t i = 0; i < ns; i++) { struct RTCRay ry; float *r = s[i].r;
          ry.org_x = r[0]; ry.org_y = r[1]; ry.org_z = r[2]; ry.dir_x = r[3]; ry.dir_y = r[4]; ry.dir_z = r[5];
          ry.tnear = 0; ry.tfar = r[6]; ry.mask = -1; ry.flags = 0; ry.time = 0;
          rtcOccluded1(scene, &ctx, &ry); blocked += ry.tfar < 0; }
      } else {
        for (size_t i = 0; i < ns; i += 16) { struct RTCRay16 ry __attribute__((aligned(64))); int valid[16] __attribute__((aligned(64)));
          for (int k = 0; k < 16; k++) { size_t q = i + k < ns ? i + k : ns - 1; float *r = s[q].r; valid[k] = i + k < ns ? -1 : 0;
            ry.org_x[k] = r[0]; ry.org_y[k] = r[1]; ry.org_z[k] = r[2]; ry.dir_x[k] = r[3]; ry.dir_y[k] = r[4]; ry.dir_z[k] = r[5];
            ry.tnear[k] = 0; ry.tfar[k] = r[6]; ry.mask[k] = -1; ry.flags[k] = 0; ry.time[k] = 0; }
          rtcOccluded16(valid, scene, &ctx, &ry);
          for (int k = 0; k < 16 && i + k < ns; k++) blocked += ry.tfar[k] < 0; }
      }
      double t2 = now();
      printf("%s: closest %zu rays %.3f s (%.2f Mrays/s, %zu hits), shadow %zu rays %.3f s (%.2f Mrays/s, %zu blocked), total %.3f s\n",
        pass ? "packets of 16, wavefront order" : "one by one, path order", nc, t1 - t0, nc / (t1 - t0) / 1e6, hits, ns, t2 - t1, ns / (t2 - t1) / 1e6, blocked, t2 - t0);
    }
  }
}
