pub trait Real {}
