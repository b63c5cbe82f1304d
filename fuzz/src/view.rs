//! The viewer's HTTP bodies (`kinetree view`'s JSON API) for the libFuzzer target `view`. The
//! API is a set of pure functions from a body to an answer, compiled here from the CLI's own
//! source; the stable counterpart is the CLI's `fuzzed_api_bodies_get_an_answer_or_a_bad_request`
//! test over the same seeds (`fuzz/seeds/view`).

#[allow(
    dead_code,
    unreachable_pub,
    reason = "only the endpoints are fuzzed, not the page's helpers"
)]
#[path = "../../crates/kinetree-cli/src/cmd/view/api.rs"]
mod api;

use kinetree::collision::{CollisionModel, CollisionOptions};
use kinetree::model::{Model, RootJoint};
use std::path::Path;

/// The Panda with its collision meshes, as `kinetree view` builds it.
fn panda() -> &'static (Model, CollisionModel) {
    static PANDA: std::sync::OnceLock<(Model, CollisionModel)> = std::sync::OnceLock::new();
    PANDA.get_or_init(|| {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/robots/panda.urdf");
        let model = Model::from_urdf_file(&path, RootJoint::Fixed).expect("the Panda loads");
        let options = CollisionOptions::default()
            .with_model_file(&path, &[])
            .skip_missing_meshes();
        let cmodel = CollisionModel::from_model(&model, &options).expect("its collision model");
        (model, cmodel)
    })
}

/// A body through `/api/fk`, `/api/ik` and `/api/collide`: each answer is a 400 with a message
/// or a 200 whose numbers are all finite (serde_json writes NaN as `null`).
pub fn view(bytes: &[u8]) {
    let (model, cmodel) = panda();
    for answer in [
        api::fk(model, bytes),
        api::ik(model, bytes),
        api::collide(model, Ok(cmodel), bytes),
    ] {
        match answer {
            Ok(v) => assert!(!has_null(&v), "null in {v}"),
            Err(e) => {
                assert_eq!(e.status, 400, "{e:?}");
                assert!(!e.message.is_empty());
            }
        }
    }
}

fn has_null(v: &serde_json::Value) -> bool {
    match v {
        serde_json::Value::Null => true,
        serde_json::Value::Array(a) => a.iter().any(has_null),
        serde_json::Value::Object(o) => o.values().any(has_null),
        _ => false,
    }
}
