/* bench/results/bvh-mft.md's kernel timings: one BVH kernel (or the frusta:16
 * soft-shadow kernel, "soft") on rtt bench's primary rays (soft: its soft
 * rays) in rtt bench's order (16x16 tiles of 4x4 blocks), one thread, best
 * thread CPU time of FRAMES, with the BVH built at LEAF / DEPTH (0: the
 * defaults), the counters of one extra frame and a checksum of the results.
 *
 *   cc -O2 -msse4.1 -I include -I bench -I optimized -I optimized/bvh -I optimized/kd -I optimized/isect \
 *      -I engine/include -I engine -o kernel_cpu_time bench/results/bvh-mft/kernel_cpu_time.c \
 *      (the libraries and link line of build/cli/CMakeFiles/rtt.dir/link.txt)
 *   kernel_cpu_time SCENE bvh-mft|bvh-packet|soft SIZE LEAF DEPTH FRAMES bench/views.json
 *
 * ISA=sse4|avx2 in the environment picks a narrower kernel. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <math.h>
#include "bench_internal.h"
#include "bench.h"
#include "bvh_kernels.h"
#include "bvh_build.h"
#include "rtt/views.h"
#include "rtt/scene.h"
static double now(void){struct timespec t;clock_gettime(CLOCK_THREAD_CPUTIME_ID,&t);return t.tv_sec+t.tv_nsec*1e-9;}
static void run_soft(rtt_scene*sc,const bench_rays*pr,const bvh_tree*tree,int frames,const char*name,int leaf,int depth){
  size_t px=(size_t)pr->width*pr->height; uint32_t*prim=malloc(px*4); float*t=malloc(px*4);
  const bvh_kernel*k=bvh_kernel_find("bvh-mft",RTT_ISA_AVX512);
  rtt_hit*h=malloc(px*sizeof*h);
  for(size_t i=0;i<px;i+=256){size_t n=px-i<256?px-i:256; bvh_query q={.rays=pr->rays+i,.count=n,.hits=h+i}; k->trace(tree,&q);}
  for(size_t i=0;i<px;i++)prim[i]=h[i].prim,t[i]=h[i].t;
  bench_soft soft={0}; rtt_error err={{0}};
  if(!bench_soft_make(sc,pr,prim,t,&soft,&err)){printf("no soft: %s\n",err.message);return;}
  uint32_t w=soft.width,hh=soft.height,tx=(w+15)/16,ty=(hh+15)/16; size_t tiles=(size_t)tx*ty;
  bvh_shadow_point*pts=malloc(px*sizeof*pts); uint32_t*first=malloc((tiles+1)*4); uint32_t*masks=calloc(px,4); uint32_t cnt=0;
  for(size_t tile=0;tile<tiles;tile++){first[tile]=cnt; for(uint32_t in=0;in<256;in++){uint32_t b=in/16,l=in%16; uint32_t x=(tile%tx)*16+(b%4)*4+l%4,y=(tile/tx)*16+(b/4)*4+l/4; if(x>=w||y>=hh||!soft.has[(size_t)y*w+x])continue; pts[cnt++]=soft.points[(size_t)y*w+x];}}
  first[tiles]=cnt;
  const char*isa=getenv("ISA"); rtt_isa ia=isa?(strcmp(isa,"sse4")==0?RTT_ISA_SSE4:strcmp(isa,"avx2")==0?RTT_ISA_AVX2:RTT_ISA_AVX512):RTT_ISA_AVX512;
  const bvh_shadow_kernel*sk=bvh_shadow_kernel_find(ia);
  bvh_counters c={0};
  for(size_t tl=0;tl<tiles;tl++){bvh_shadow_query q={.points=pts+first[tl],.count=first[tl+1]-first[tl],.sets=&soft.sets,.epsilon=soft.epsilon,.occluded=masks+first[tl],.counters=&c}; sk->trace(tree,&q);}
  unsigned long long sum=0; for(uint32_t i=0;i<cnt;i++) sum=sum*31+masks[i];
  double best=1e9;
  for(int f=0;f<frames;f++){double s=now(); for(size_t tl=0;tl<tiles;tl++){bvh_shadow_query q={.points=pts+first[tl],.count=first[tl+1]-first[tl],.sets=&soft.sets,.epsilon=soft.epsilon,.occluded=masks+first[tl]}; sk->trace(tree,&q);} double e=now()-s; if(e<best)best=e;}
  double quads=(double)soft.rays.width*soft.rays.height/4.0;
  printf("%s frusta:16 %s leaf %d depth %d: depth %u  %.2f Mr/s (best cpu %.4f s)  N %.3f I %.3f tris %.0fK isec %.0fK  chk %llx\n",name,rtt_isa_name(sk->isa),leaf,depth,tree->info.depth,(double)soft.rays.active/best/1e6,best,c.aabb_tests/quads,c.isect_tests/quads,c.triangles/1e3,c.isect_tests/1e3,sum);
}
int main(int argc,char**argv){
  if(argc<8){fprintf(stderr,"usage: kernel_cpu_time SCENE KERNEL|soft SIZE LEAF DEPTH FRAMES VIEWS\n");return 2;}
  const char*path=argv[1]; const char*kname=argv[2]; int size=atoi(argv[3]); int leaf=atoi(argv[4]); int depth=atoi(argv[5]); int frames=atoi(argv[6]); const char*views=argv[7];
  rtt_error err={{0}};
  rtt_scene*sc=rtt_scene_load(path,NULL,&err); if(!sc){fprintf(stderr,"%s\n",err.message);return 1;}
  rtt_view_list vl; rtt_views_load(views,&vl,&err);
  char name[256]; const char*b=strrchr(path,'/'); snprintf(name,sizeof name,"%s",b?b+1:path); char*d=strchr(name,'.'); if(d)*d=0;
  const rtt_view*v=rtt_views_find(&vl,name); if(v) rtt_bench_apply_view(sc,v,&err);
  bench_rays pr={0}; bench_rays_primary(sc,size,size,&pr);
  bvh_tree tree; memset(&tree,0,sizeof tree);
  bvh_build_options bo={.leaf_size=leaf,.max_depth=depth,.threads=1};
  double t0=now(); bvh_build_sah(sc,&bo,&tree,&err); double tb=now()-t0; tree.watertight=true;
  if(!strcmp(kname,"soft")){run_soft(sc,&pr,&tree,frames,name,leaf,depth);return 0;}
  const bvh_kernel*k=bvh_kernel_find(kname,getenv("ISA")?(strcmp(getenv("ISA"),"sse4")==0?RTT_ISA_SSE4:strcmp(getenv("ISA"),"avx2")==0?RTT_ISA_AVX2:RTT_ISA_AVX512):RTT_ISA_AVX512);
  uint32_t w=size,h=size,tx=(w+15)/16,ty=(h+15)/16; size_t slots=(size_t)tx*ty*256;
  rtt_ray*ord=malloc(slots*sizeof*ord); rtt_hit*hits=malloc(slots*sizeof*hits);
  for(size_t i=0;i<slots;i++){uint32_t tile=i/256,in=i%256,bl=in/16,l=in%16; uint32_t x=(tile%tx)*16+(bl%4)*4+l%4,y=(tile/tx)*16+(bl/4)*4+l/4; ord[i]=pr.rays[(size_t)y*w+x];}
  bvh_counters c={0};
  for(size_t t=0;t<slots/256;t++){bvh_query q={.rays=ord+t*256,.count=256,.hits=hits+t*256,.counters=&c}; k->trace(&tree,&q);}
  unsigned long long sum=0; for(size_t i=0;i<slots;i++) sum=sum*31+hits[i].prim+ (unsigned)(hits[i].t*1000);
  double best=1e9;
  for(int f=0;f<frames;f++){double s=now(); for(size_t t=0;t<slots/256;t++){bvh_query q={.rays=ord+t*256,.count=256,.hits=hits+t*256}; k->trace(&tree,&q);} double e=now()-s; if(e<best)best=e;}
  double quads=slots/4.0;
  printf("%s %s %s leaf %d depth %d: depth %u nodes %u  %.2f Mr/s (best cpu %.4f s)  N %.3f I %.3f tris %.3f  build %.3fs  chk %llx\n",name,k->name,rtt_isa_name(k->isa),leaf,depth,tree.info.depth,tree.node_count,slots/best/1e6,best,c.aabb_tests/quads,c.isect_tests/quads,c.triangles/quads,tb,sum);
  return 0;}
