#include <dawnforge/core/import.hpp>
#include <cstdio>
#include <cmath>
#include <map>
#include <tuple>
using namespace dawnforge;
int main(){
  auto nodes=loadMeshNodes("/tmp/demo/city/city.glb");
  for(auto&n:nodes){ if(n.name!="building_00000_lod0") continue; auto&m=n.mesh;
    // find trim triangles facing up with area ~0.2 (half of 0.39)
    int shown=0;
    using K=std::tuple<long,long,long>;
    auto key=[&](glm::vec3 p){return K{lround(p.x*1e4),lround(p.y*1e4),lround(p.z*1e4)};};
    std::multimap<std::pair<K,K>,size_t> edges;
    for(size_t t=0;t<m.indices.size()/3;++t) for(int k=0;k<3;++k){ K a=key(m.positions[m.indices[3*t+k]]), b=key(m.positions[m.indices[3*t+(k+1)%3]]); if(b<a) std::swap(a,b); edges.insert({{a,b},t}); }
    for(size_t t=0;t<m.indices.size()/3 && shown<2;++t){ if(m.materialIds[m.indices[3*t]]!=7) continue;
      glm::vec3 a=m.positions[m.indices[3*t]],b=m.positions[m.indices[3*t+1]],c=m.positions[m.indices[3*t+2]];
      glm::vec3 nn=glm::cross(b-a,c-a); float ar=0.5f*glm::length(nn); nn=glm::normalize(nn);
      if(nn.y<0.99f || ar<0.15f || ar>0.3f) continue; ++shown;
      printf("tri %zu area %.3f: (%.3f %.3f %.3f) (%.3f %.3f %.3f) (%.3f %.3f %.3f)\n",t,ar,a.x,a.y,a.z,b.x,b.y,b.z,c.x,c.y,c.z);
      for(int k=0;k<3;++k){ K p=key(m.positions[m.indices[3*t+k]]), q=key(m.positions[m.indices[3*t+(k+1)%3]]); if(q<p) std::swap(p,q);
        auto r=edges.equal_range({p,q}); printf("  edge %d shared by:",k); for(auto it=r.first;it!=r.second;++it){ size_t u=it->second; glm::vec3 aa=m.positions[m.indices[3*u]],bb=m.positions[m.indices[3*u+1]],cc=m.positions[m.indices[3*u+2]]; glm::vec3 n2=glm::normalize(glm::cross(bb-aa,cc-aa)); printf(" %zu(m%d n %.1f %.1f %.1f)",u,m.materialIds[m.indices[3*u]],n2.x,n2.y,n2.z);} printf("\n"); }
      // vertices near this tri's first vertex
      for(size_t v=0; v<m.positions.size(); ++v){ if(glm::length(m.positions[v]-a)<0.01f && glm::length(m.positions[v]-a)>0) printf("  near vertex %zu at dist %g\n", v, glm::length(m.positions[v]-a)); }
    }
  }
}
