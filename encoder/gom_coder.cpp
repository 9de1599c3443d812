#include "encoder/gom_coder.h"

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <map>
#include <memory>
#include <stdexcept>
#include <utility>

#include "bitstream/syntax.h"
#include "common/core/error.h"
#include "common/geometry/keyframes.h"
#include "decoder/gom_decoder.h"
#include "encoder/attributes_encoder.h"
#include "encoder/imesh_encoder.h"
#include "encoder/keyframe_selection.h"
#include "encoder/pmesh_encoder.h"

namespace tdvo {

namespace {

// Codes one GOM. The frames come out of a GomDecoder (decoder/gom_decoder.h), the decoder's
// GOM loop, for which this class is the source of units (GomUnits): when the decoder needs the
// I mesh of a frame, or the P mesh of a keyframe, the encoder codes it there and then, from the
// reference the decoder holds, and hands it the payload. The frames the encoder reports are
// then the decoder's, made by the decoder's code; for P meshes the reconstruction the encoder's
// own writer made is checked against them (closed loop).
class GomCoder : public GomUnits {
 public:
  GomCoder(const EncoderParams& params, const Grid& grid, size_t first, std::vector<Mesh> frames,
           const std::function<std::string(size_t)>& frameName, const GomContinuation* continuation,
           GomContinuation* next)
      : params_(params),
        grid_(grid),
        first_(first),
        frames_(std::move(frames)),
        frameName_(frameName),
        continuation_(continuation),
        next_(next) {
    pmParams_.gridBits = params.gridBits;
    pmParams_.quantStep = params.motionQuantStep;
    pmParams_.maxDepth = std::min(params.maxOctreeDepth, params.gridBits);
  }

  GomGeometry code() {
    const size_t count = frames_.size();
    const bool pMeshes = params_.pmeshMode != PMeshMode::kIntra;
    // Only the quantised frames are kept: each input mesh is released once on the grid, and in a
    // GOM of P meshes only the first frame keeps its triangles (memory is what bounds the
    // largest meshes a GOM can hold).
    for (Mesh& mesh : frames_) {
      inputs_.push_back(grid_.quantise(mesh));
      mesh = Mesh();
      // In a GOM of P meshes the first frame speaks for all (the others must have its triangles).
      countDegenerateTriangles(inputs_.size() - 1, inputs_.back());
    }
    checkAttributes();
    if (pMeshes) {
      checkConstantConnectivity(inputs_);
      for (size_t k = 1; k < count; ++k) {
        std::vector<Triangle>().swap(inputs_[k].triangles);
        inputs_[k].attributes = MeshAttributes();  // the first frame's speak for all
      }
    }

    const size_t inputVertices = inputs_[0].positions.size();
    // Continue the previous GOM's connectivity (no I mesh) when it is the same, and so are the
    // attributes the I mesh carries for all its frames.
    const bool continues = pMeshes && continuation_ && continuation_->iMesh &&
                           continuation_->inputVertices == inputVertices &&
                           continuation_->inputTriangles == inputs_[0].triangles &&
                           continuation_->normalMode == normalMode_ &&
                           continuation_->inputAttributes == spanAttributes(inputs_[0]);

    GomHeader gh;
    gh.gh_random_access = continues ? 0 : 1;
    gh.gh_first_frame = static_cast<uint32_t>(first_);
    gh.gh_frame_count = static_cast<uint16_t>(count);
    gh.gh_pmesh_mode = static_cast<uint8_t>(params_.pmeshMode);
    gh.gh_motion_quant_step = static_cast<uint16_t>(pmParams_.quantStep);
    gh.gh_max_octree_depth = static_cast<uint8_t>(pmParams_.maxDepth);
    if (pMeshes && (params_.bMeshGap == 0 || count <= 2)) {
      std::vector<std::vector<Vec3i>> positions;
      for (const IntMesh& m : inputs_)
        positions.push_back(m.positions);
      const std::vector<int> keys =
          selectKeyframes(positions, params_.keyframeCount, params_.keyframeMaxError);
      gh.keyframes.assign(keys.begin(), keys.end());
    }
    if (pMeshes && params_.bMeshGap > 0 && count > 2) {
      // Keyframes every BMeshGap frames and the last; B meshes between them.
      gh.keyframes.clear();
      for (size_t k = 0; k < count - 1; k += static_cast<size_t>(params_.bMeshGap))
        gh.keyframes.push_back(static_cast<uint16_t>(k));
      gh.keyframes.push_back(static_cast<uint16_t>(count - 1));
      gh.gh_pmesh_mode = kGhD3dmcBMeshes;
      gh.gh_bmesh_quant_step = static_cast<uint16_t>(params_.effectiveBMeshQuantStep());
      codeFrames(gh, continues, false);
    } else if (pMeshes && params_.keyframeLambda != 0 && count > 2)
      codeRdKeyframes(gh, continues);
    else
      codeFrames(gh, continues, false);

    // (`next` may be `continuation` itself: read it before writing.)
    if (next_ && pMeshes) {
      GomContinuation following;
      following.iMesh = continues ? continuation_->iMesh
                                  : std::make_shared<const IMeshEncoding>(out_.iMeshes.back());
      following.inputTriangles = std::move(inputs_[0].triangles);
      following.inputVertices = inputVertices;
      following.inputAttributes =
          continues ? continuation_->inputAttributes : spanAttributes(inputs_[0]);
      following.normalMode = normalMode_;
      following.last = out_.frames.back().positions;  // the last keyframe: the GOM's last frame
      *next_ = std::move(following);
    } else if (next_) {
      *next_ = GomContinuation();
    }
    return std::move(out_);
  }

  // GomUnits: the I mesh of GOM frame k, coded now.
  void iMesh(uint32_t k, IntMesh& mesh, std::string& where) override {
    if (k == 0 && iMeshCoded_) {  // a GOM coded again (codeRdKeyframes): the same I mesh
      out_.units.insert(out_.units.end(), iMeshUnits_.begin(), iMeshUnits_.end());
      out_.iMeshes.push_back(*iMeshCoded_);
    } else {
      const size_t mark = out_.units.size();
      codeIMesh(k, inputs_[k]);
      if (k == 0 && keepIMesh_) {
        iMeshUnits_.assign(out_.units.begin() + static_cast<std::ptrdiff_t>(mark),
                           out_.units.end());
        iMeshCoded_ = std::make_unique<IMeshEncoding>(out_.iMeshes.back());
      }
    }
    mesh = out_.iMeshes.back().decoded;
    where = name(k);  // its connectivity is the input frame's
  }

  // GomUnits: the P mesh of keyframe k, coded now from the decoder's reference (the previous
  // decoded keyframe).
  PMeshPayload pMesh(uint32_t k) override {
    const IMeshEncoding& i = out_.iMeshes.back();
    // The keyframe's target in the GOM's vertex order (Draco's decoded order).
    target_.resize(i.inputIndex.size());
    for (size_t j = 0; j < target_.size(); ++j)
      target_[j] = inputs_[k].positions[i.inputIndex[j]];
    PMeshEncoding p = codePMesh(decoder_.reference(), target_, decoder_.params(), lambdaOf(k));
    PMeshUnit pm;
    pm.pm_frame = static_cast<uint32_t>(first_ + k);
    pm.pm_cabac_payload = std::move(p.payload);
    out_.units.push_back({UnitType::kPMesh, serialise(pm)});
    pMeshBits_[k] = 8.0 * static_cast<double>(out_.units.back().payload.size());
    payload_ = std::move(pm.pm_cabac_payload);
    pending_[k] = std::move(p.reconstruction);
    return {payload_.data(), payload_.size(), "encoder's own P mesh", nullptr};
  }

 private:
  std::string name(size_t k) const { return frameName_(first_ + k); }

  // The GOM's own P-mesh Lambda (its keyframes' and, without B meshes, every P mesh's).
  double pLambda() const { return params_.lambdaFor(pmParams_.quantStep); }

  // The Lambda of GOM frame k's P mesh: the GOM's, or, for a B mesh, its level's.
  double lambdaOf(size_t k) const {
    const std::vector<uint16_t>& keys = bMeshKeyframes_;
    const auto b = std::upper_bound(keys.begin(), keys.end(), k);
    if (keys.empty() || b == keys.begin() || b == keys.end() || b[-1] == k) return pLambda();
    return params_.bMeshLambda(bMeshLevel(b[-1], *b, static_cast<int>(k)));
  }

  // The P mesh of `target` predicted from `previous` (both in the GOM's vertex order).
  // `params`: the GOM's (pmParams_), or a B mesh's.
  PMeshEncoding codePMesh(const std::vector<Vec3i>& previous, const std::vector<Vec3i>& target,
                          const PMeshParams& params, double lambda) {
    return params_.pmeshMode == PMeshMode::kD3dmc
               ? encodePMesh(decoder_.topology(), previous, target, params, lambda)
               : encodeTemporalDpcm(previous, target, params);
  }

  // Codes the GOM with the keyframes of `gh` into out_ (the GOM header, its units and frames),
  // the frames made by the decoder's GOM loop. With `keepInputs` the quantised inputs are
  // copied into the frames, else moved (the GOM is not coded again).
  void codeFrames(const GomHeader& gh, bool continues, bool keepInputs) {
    out_.units.push_back({UnitType::kGomHeader, serialise(gh)});
    bMeshKeyframes_ = hasBMeshes(gh) ? gh.keyframes : std::vector<uint16_t>();
    out_.keyframes = gh.keyframes.empty() ? inputs_.size() : gh.keyframes.size();
    // A continuing GOM starts from the previous GOM's connectivity and last frame.
    GomReference continued;
    if (continues) {
      out_.iMeshes.push_back(*continuation_->iMesh);
      continued.mesh = {continuation_->last, continuation_->iMesh->decoded.triangles, {}};
    }
    pMeshBits_.assign(inputs_.size(), 0.0);
    pending_.clear();
    decoder_.start(gh, params_.gridBits, "encoder's own GOM", continues ? &continued : nullptr);
    for (size_t k = 0; k < inputs_.size(); ++k) {
      const std::vector<Vec3i>& positions = decoder_.next(*this);
      const auto coded = pending_.find(k);
      if (coded != pending_.end()) {
        if (positions != coded->second)
          throw std::logic_error("P-mesh reconstruction differs from the decoder's (frame " +
                                 std::to_string(first_ + k) + ")");
        pending_.erase(coded);
      }
      emit(positions,
           keepInputs ? std::vector<Vec3i>(inputs_[k].positions) : std::move(inputs_[k].positions));
    }
  }

  // KeyframeLambda: the GOM's keyframes chosen by rate and distortion (docs/options.md).
  // 1. The GOM is coded with every frame a keyframe (A): the real rate and error of every
  //    one-frame interval, and the decoded frames the longer intervals are predicted from.
  // 2. selectKeyframesRd chooses the keyframes: an interval a .. b costs the squared error of
  //    the frames a + 1 .. b against the quantised input (keyframe b's own quantisation, the
  //    interpolated frames exactly) plus lambda times the bits of b's P mesh, which is coded
  //    for the estimate from A's decoded frame a (the closed loop of the chosen keyframes
  //    predicts from its own decoded keyframe a, which may differ a little).
  // 3. When that is not every frame, the GOM is coded again with the chosen keyframes (B), and
  //    B is kept only when its real J is smaller than A's: never worse than every frame.
  // Every step is a function of the GOM alone: the same stream for any Threads.
  void codeRdKeyframes(GomHeader gh, bool continues) {
    const int n = static_cast<int>(inputs_.size());
    const double lambda = params_.effectiveKeyframeLambda();
    const GomGeometry base = out_;  // what checkAttributes said; no unit yet
    gh.keyframes.resize(inputs_.size());
    for (int k = 0; k < n; ++k)
      gh.keyframes[k] = static_cast<uint16_t>(k);
    keepIMesh_ = true;
    codeFrames(gh, continues, true);
    GomGeometry all = std::move(out_);
    const std::vector<double> allBits = pMeshBits_;

    // The quantised input in the GOM's vertex order (the order P meshes are coded in).
    const std::vector<uint32_t>& index = all.iMeshes.back().inputIndex;
    std::vector<std::vector<Vec3i>> target(inputs_.size(), std::vector<Vec3i>(index.size()));
    for (int k = 0; k < n; ++k)
      for (size_t j = 0; j < index.size(); ++j)
        target[k][j] = all.frames[k].input[index[j]];
    const auto squared = [](const std::vector<Vec3i>& p, const std::vector<Vec3i>& q) {
      double sum = 0;
      for (size_t j = 0; j < p.size(); ++j)
        for (int c = 0; c < 3; ++c) {
          const double e = double(p[j][c]) - double(q[j][c]);
          sum += e * e;
        }
      return sum;
    };
    std::vector<Vec3i> between;
    const auto interpolationError = [&](const std::vector<Vec3i>& ka, const std::vector<Vec3i>& kb,
                                        int a, int b) {
      double sum = 0;
      for (int f = a + 1; f < b; ++f) {
        interpolateFrame(ka, kb, a, b, f, between);
        sum += squared(between, target[f]);
      }
      return sum;
    };
    const auto jOf = [&](const GomGeometry& g, const std::vector<double>& bits) {
      double j = 0;
      for (int k = 0; k < n; ++k)
        j += squared(g.frames[k].positions, target[k]) + lambda * bits[k];
      return j;
    };

    const auto bound = [&](int a, int b) {
      return interpolationError(all.frames[a].positions, target[b], a, b);
    };
    const auto cost = [&](int a, int b) {
      const std::vector<Vec3i>& ka = all.frames[a].positions;
      if (b == a + 1) return squared(all.frames[b].positions, target[b]) + lambda * allBits[b];
      const PMeshEncoding p = codePMesh(ka, target[b], pmParams_, pLambda());
      PMeshUnit pm;
      pm.pm_frame = static_cast<uint32_t>(first_ + b);
      pm.pm_cabac_payload = p.payload;
      const double bits = 8.0 * static_cast<double>(serialise(std::move(pm)).size());
      return squared(p.reconstruction, target[b]) + interpolationError(ka, p.reconstruction, a, b) +
             lambda * bits;
    };
    const std::vector<int> keys = selectKeyframesRd(n, kKeyframeRdMaxGap, bound, cost);
    if (static_cast<int>(keys.size()) == n) {
      out_ = std::move(all);
      return;
    }
    out_ = base;
    gh.keyframes.assign(keys.begin(), keys.end());
    codeFrames(gh, continues, false);  // `all` holds the inputs too
    if (jOf(out_, pMeshBits_) < jOf(all, allBits))
      out_.warnings = std::move(all.warnings);  // said once, when the I mesh was coded
    else
      out_ = std::move(all);
  }

  // Triangles with a repeated vertex have no area and no orientation; Draco's Edgebreaker cannot
  // code them (draco_encoder drops them). They are kept, in every mode: the VERTEX_ORDER unit
  // carries them (encodeIMesh); codeIMesh counts them in a warning. A mesh of nothing else has
  // no surface to code.
  void countDegenerateTriangles(size_t k, const IntMesh& mesh) const {
    const bool any =
        std::any_of(mesh.triangles.begin(), mesh.triangles.end(),
                    [](const Triangle& t) { return t[0] != t[1] && t[1] != t[2] && t[0] != t[2]; });
    check(any, name(k) + ": every triangle has a repeated vertex: no triangle is left to code");
    // Draco's encoder takes time quadratic in the triangles around one vertex (its corner
    // table); a vertex of more is refused before it (kMaxVertexTriangles, imesh_encoder.h).
    std::vector<uint32_t> around(mesh.positions.size(), 0);
    for (const Triangle& t : mesh.triangles)
      if (t[0] != t[1] && t[1] != t[2] && t[0] != t[2])
        for (uint32_t v : t)
          check(++around[v] <= kMaxVertexTriangles,
                name(k) + ": vertex " + std::to_string(v) + " is a corner of more than " +
                    std::to_string(kMaxVertexTriangles) +
                    " triangles (Draco's encoding time grows with the square of it)");
  }

  // P meshes carry positions only: the GOM's frames must share the first frame's connectivity.
  void checkConstantConnectivity(const std::vector<IntMesh>& inputs) const {
    const IntMesh& a = inputs[0];
    for (size_t k = 1; k < inputs.size(); ++k) {
      const IntMesh& b = inputs[k];
      check(a.positions.size() == b.positions.size(),
            name(k) + ": " + std::to_string(b.positions.size()) +
                " vertices, but the GOM's first frame (" + name(0) + ") has " +
                std::to_string(a.positions.size()) +
                " (P meshes need constant connectivity; use GOMSize or PMeshMode intra)");
      check(a.triangles == b.triangles, name(k) +
                                            ": connectivity differs from the GOM's first frame (" +
                                            name(0) + "); P meshes need constant connectivity");
    }
  }

  void codeIMesh(size_t k, const IntMesh& input) {
    IMeshEncoding i = encodeIMesh(input, params_.gridBits, params_.dracoSpeed,
                                  params_.inputTriangleOrder, params_.iMeshQuantStep);
    // Draco does not keep vertices that no triangle uses; say so rather than drop them quietly.
    // Counted in the output order, not in Draco's vertices: the copies Draco makes of a
    // non-manifold vertex merge back into it there, and could hide a dropped vertex.
    if (i.order.numVertices != input.positions.size())
      out_.warnings.push_back(
          name(k) + ": " + std::to_string(input.positions.size()) + " vertices in, " +
          std::to_string(i.order.numVertices) +
          " out: " + std::to_string(input.positions.size() - i.order.numVertices) +
          " that no triangle uses are dropped (Draco keeps only vertices of triangles; later "
          "vertices shift down)");
    if (i.keptDegenerate + i.droppedDegenerate > 0)
      out_.warnings.push_back(
          name(k) + ": " + std::to_string(i.keptDegenerate + i.droppedDegenerate) + " of " +
          std::to_string(input.triangles.size()) +
          " triangles have a repeated vertex (degenerate); kept (carried outside Draco)" +
          (i.droppedDegenerate > 0 ? ", except " + std::to_string(i.droppedDegenerate) +
                                         " using a vertex no other triangle uses: dropped"
                                   : std::string()));
    if (i.unmatchedTriangles > 0)
      out_.warnings.push_back(name(k) + ": " + std::to_string(i.unmatchedTriangles) +
                              " decoded triangles have no input twin; P meshes of this GOM "
                              "may predict poorly");
    IMeshUnit im;
    im.im_frame = static_cast<uint32_t>(first_ + k);
    im.im_quant_step = static_cast<uint16_t>(i.quantStep);
    im.im_draco_payload = i.payload;
    out_.units.push_back({UnitType::kIMesh, serialise(std::move(im))});
    VertexOrderUnit vo;
    vo.vo_frame = static_cast<uint32_t>(first_ + k);
    vo.vo_num_vertices = i.order.numVertices;
    vo.vo_triangle_order = i.triangleOrder ? 1 : 0;
    vo.vo_cabac_payload = i.orderPayload;
    out_.units.push_back({UnitType::kVertexOrder, serialise(std::move(vo))});
    if (params_.attributesPresent) {
      AttributesEncoding a = encodeAttributes(input, i, params_.textureCoordinates, normalMode_,
                                              static_cast<uint32_t>(first_ + k), name(k),
                                              params_.uvQuantBits, params_.normalQuantBits);
      out_.units.push_back({UnitType::kAttributes, std::move(a.payload)});
      i.attributes = std::move(a.decoded);
    }
    out_.iMeshes.push_back(std::move(i));
  }

  // What of a frame's attributes must stay the same for the frames coded from its I mesh: its
  // texture coordinates, and its normals when they are coded.
  MeshAttributes spanAttributes(const IntMesh& frame) const {
    MeshAttributes a = frame.attributes;
    if (normalMode_ == NormalMode::kComputed) {
      a.normals.clear();
      a.normalTriangles.clear();
    }
    return a;
  }

  // The GOM's attributes (docs/user-guide.md, "Texture coordinates and normals"): those the
  // cfg drops are dropped; the rest must be in the stream (its first frame decided) and, in a
  // GOM of P meshes, the texture coordinates the same in every frame; the normals are coded
  // when they are (or when Normals says so), else computed (normalMode_).
  // Why a GOM codes no normals: the input has none, or Normals none left them out.
  const char* noNormals() const {
    return params_.normals == NormalsChoice::kNone ? "none (Normals none: left out)"
                                                   : "none in the input";
  }

  // How a frame's attribute (values and index triangles) compares with the GOM's first frame's,
  // bit for bit (-0 is not 0; a NaN is itself): the same lists, other lists that give every
  // corner the same value (another `vt` or `vn` order), or different.
  enum class Same { kLists, kPerCorner, kNot };
  template <class V>
  static Same compare(const std::vector<V>& a, const std::vector<Triangle>& aIndices,
                      const std::vector<V>& b, const std::vector<Triangle>& bIndices) {
    const auto same = [](const V& x, const V& y) { return std::memcmp(&x, &y, sizeof(V)) == 0; };
    if (aIndices.size() != bIndices.size()) return Same::kNot;
    if (a.size() == b.size() && aIndices == bIndices &&
        std::equal(a.begin(), a.end(), b.begin(), same))
      return Same::kLists;
    for (size_t t = 0; t < aIndices.size(); ++t)
      for (int c = 0; c < 3; ++c)
        if (!same(a[aIndices[t][c]], b[bIndices[t][c]])) return Same::kNot;
    return Same::kPerCorner;
  }

  void checkAttributes() {
    for (size_t k = 0; k < inputs_.size(); ++k) {
      MeshAttributes& a = inputs_[k].attributes;
      if (!params_.textureCoordinates) a.uvs.clear(), a.uvTriangles.clear();
      if (params_.normals == NormalsChoice::kNone) a.normals.clear(), a.normalTriangles.clear();
      check(params_.attributesPresent || a.empty(),
            name(k) +
                ": has texture coordinates or normals, but the sequence's first frame has "
                "none, so the stream carries none (give the first frame them too, or set "
                "TextureCoordinates 0 and Normals none)");
    }
    const MeshAttributes& first = inputs_[0].attributes;
    const bool pMeshes = params_.pmeshMode != PMeshMode::kIntra;
    bool normalsChange = false;
    // Frames whose lists give every corner the first frame's values in another order: coded as
    // the first frame's, exact per corner; only the list order is the first frame's, said.
    struct Reordered {
      size_t count = 0, first = 0;
    } uvsReordered, normalsReordered;
    const auto row = [](const MeshAttributes& m) {
      return m.uvOrigin == UvOrigin::kTop ? "top row (glTF's convention)"
                                          : "bottom row (OBJ's and PLY's convention)";
    };
    const std::string intraHint =
        "; a GOM of P meshes carries its I mesh's texture coordinates for every frame: use "
        "shorter GOMs (GOMSize, GOMListFile) or PMeshMode intra";
    for (size_t k = 1; pMeshes && k < inputs_.size(); ++k) {
      const MeshAttributes& a = inputs_[k].attributes;
      const Same uvs = compare(a.uvs, a.uvTriangles, first.uvs, first.uvTriangles);
      check(uvs != Same::kNot, name(k) +
                                   ": texture coordinates differ from those of the GOM's first "
                                   "frame (" +
                                   name(0) + ")" + intraHint);
      check(a.uvs.empty() || a.uvOrigin == first.uvOrigin,
            name(k) + ": texture coordinates measured from the image's " + row(a) +
                ", those of the GOM's first frame (" + name(0) + ") from its " + row(first) +
                intraHint);
      if (uvs == Same::kPerCorner && uvsReordered.count++ == 0) uvsReordered.first = k;
      check(a.hasNormals() == first.hasNormals(),
            name(k) + (a.hasNormals() ? ": has normals" : ": has no normals") +
                ", unlike the GOM's first frame (" + name(0) + ")");
      const Same normals =
          compare(a.normals, a.normalTriangles, first.normals, first.normalTriangles);
      if (normals == Same::kPerCorner && normalsReordered.count++ == 0) normalsReordered.first = k;
      normalsChange |= normals == Same::kNot;
    }
    const auto sayReordered = [this](const Reordered& r, const char* what) {
      if (r.count == 0) return;
      out_.warnings.push_back(
          name(r.first) +
          (r.count > 1 ? " and " + std::to_string(r.count - 1) + " more frames of its GOM list"
                       : " lists") +
          " the " + what + " of the GOM's first frame (" + name(0) +
          ") in another order (the same value at every corner): the decoded frames list them "
          "in the first frame's order");
    };
    sayReordered(uvsReordered, "texture coordinates");
    const NormalsChoice choice = params_.normals;
    if (!pMeshes) {
      // Every frame is an I mesh: its own normals, coded exactly unless Normals computed.
      bool any = false;
      for (const IntMesh& m : inputs_)
        any |= m.attributes.hasNormals();
      normalMode_ = !any                                 ? NormalMode::kNone
                    : choice == NormalsChoice::kComputed ? NormalMode::kComputed
                                                         : NormalMode::kPerVertex;
      out_.normals = !any ? noNormals()
                     : normalMode_ == NormalMode::kComputed
                         ? "computed by the decoder from each decoded frame"
                         : "coded exactly in every frame";
      return;
    }
    if (!first.hasNormals()) {
      normalMode_ = NormalMode::kNone;
      out_.normals = noNormals();
      return;
    }
    check(!(normalsChange && choice == NormalsChoice::kCoded),
          name(0) + " .. " + name(inputs_.size() - 1) +
              ": normals change within the GOM, and Normals coded carries the I mesh's for "
              "every frame: set Normals auto or computed, or use PMeshMode intra");
    const bool computed =
        choice == NormalsChoice::kComputed || (choice == NormalsChoice::kAuto && normalsChange);
    if (!computed) sayReordered(normalsReordered, "normals");
    normalMode_ = computed ? NormalMode::kComputed : NormalMode::kPerVertex;  // or per corner
    out_.normals = computed ? "computed by the decoder from each decoded frame" +
                                  std::string(normalsChange ? " (they change within the GOM)" : "")
                            : "coded exactly, once per I mesh";
  }

  // The next frame of the GOM is final; `input` (its quantised input positions) is not needed
  // here any more.
  void emit(const std::vector<Vec3i>& positions, std::vector<Vec3i>&& input) {
    out_.frames.push_back({positions, out_.iMeshes.size() - 1, std::move(input)});
  }

  const EncoderParams& params_;
  const Grid& grid_;
  size_t first_;
  std::vector<Mesh> frames_;  // released frame by frame as they are quantised
  const std::function<std::string(size_t)>& frameName_;
  const GomContinuation* continuation_;
  GomContinuation* next_;
  PMeshParams pmParams_;
  std::vector<IntMesh> inputs_;  // the frames on the grid
  // How the GOM's normals are carried: kNone, kComputed, or coded (kPerVertex stands for
  // coded; encodeAttributes chooses per vertex or per corner).
  NormalMode normalMode_ = NormalMode::kNone;
  GomDecoder decoder_;            // makes the GOM's frames from the units coded here
  std::vector<Vec3i> target_;     // a keyframe's input in the GOM's vertex order
  std::vector<uint8_t> payload_;  // the last P mesh's payload, while the decoder reads it
  // The encoder's reconstruction of each P or B mesh coded, by GOM frame, until the decoder's
  // GOM loop hands that frame out (with B meshes, a few frames later: at most about log2 of
  // BMeshGap + 1 are waiting).
  std::map<size_t, std::vector<Vec3i>> pending_;
  std::vector<double> pMeshBits_;         // per GOM frame: its P-mesh unit's bits (0: none)
  std::vector<uint16_t> bMeshKeyframes_;  // with B meshes, the GOM's keyframes; else empty
  // codeRdKeyframes codes a GOM twice: the I mesh's units and encoding from the first time.
  bool keepIMesh_ = false;
  std::vector<GomGeometry::Unit> iMeshUnits_;
  std::unique_ptr<IMeshEncoding> iMeshCoded_;
  GomGeometry out_;
};

}  // namespace

GomGeometry encodeGomGeometry(const EncoderParams& params, const Grid& grid, size_t first,
                              std::vector<Mesh> frames,
                              const std::function<std::string(size_t)>& frameName,
                              const GomContinuation* continuation, GomContinuation* next) {
  check(!frames.empty(), "a GOM needs at least one frame");
  return GomCoder(params, grid, first, std::move(frames), frameName, continuation, next).code();
}

}  // namespace tdvo
