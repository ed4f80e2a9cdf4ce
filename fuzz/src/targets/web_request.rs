//! What reaches hal-web's API: header lines and a JSON body
//! ([`hal_web::fuzzing::request`]), through the guard (token, Host,
//! same origin, read-only) and the checks of change, stream and machine
//! requests.

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "web_request",
    run: hal_web::fuzzing::request,
    dictionary: &[
        "Host: ", "Origin: ", "X-HAL-Token: ", "Sec-Fetch-Site: ", "same-origin", "cross-site",
        "http://", "127.0.0.1", "localhost", "[::1]", ":8338", "\n", "\n\n",
        "0123456789abcdef0123456789abcdef0123456789abcdef", "{\"command\":\"setp\",\"args\":[",
        "\"sets\"", "\"net\"", "\"unlinkp\"", "\"loadusr\"", "{\"items\":[{\"kind\":\"pin\",\"name\":",
        "{\"action\":\"machine-on\"}", "]}", "\"",
    ],
    generate: None,
};
