// ALVideoDevice for the real naoqi_driver, relayed from the fake NAOqi's Python service.
//
// NAOqi's ALVideoDevice.getImageRemote answers an ALValue array: a list of dynamic values whose
// 7th is the image as Raw. naoqi_driver reads it with asListValuePtr() and content() on each
// element (src/tools/from_any_value.cpp:28-181), so every element must be a dynamic value. A
// Python qi service can declare a typed tuple with a Raw member (signature "(iiiiiiriffff)") but
// not a dynamic holding Raw (qi 3.1.5 turns a bytes inside a dynamic into its str() text). This
// relay asks the Python service (FakeVideoFrames, typed) and answers the driver as NAOqi does.
//
//   video_relay tcp://127.0.0.1:9559
#include <iostream>
#include <string>
#include <vector>
#include <boost/function.hpp>
#include <qi/anyobject.hpp>
#include <qi/applicationsession.hpp>
#include <qi/buffer.hpp>
#include <qi/session.hpp>
#include <qi/type/dynamicobjectbuilder.hpp>

int main(int argc, char** argv)
{
  if (argc < 2) {
    std::cerr << "usage: video_relay <url of the fake NAOqi>" << std::endl;
    return 2;
  }
  qi::SessionPtr session = qi::makeSession();
  session->connect(argv[1]).value();
  qi::AnyObject frames = session->service("FakeVideoFrames").value();

  boost::function<std::string(const std::string&, int, int, int, int)> subscribe =
    [frames](const std::string& name, int camera, int resolution, int colorspace, int fps) {
      return frames.call<std::string>("subscribeCamera", name, camera, resolution, colorspace, fps);
    };
  boost::function<bool(const std::string&)> unsubscribe = [frames](const std::string& handle) {
    return frames.call<bool>("unsubscribe", handle);
  };
  boost::function<qi::AnyValue(const std::string&)> image = [frames](const std::string& handle) {
    qi::AnyValue typed;
    try {
      typed = frames.call<qi::AnyValue>("getImageRemote", handle);
    } catch (const std::exception& e) {
      // a camera with no image: an empty answer, which the driver handles ("Cannot retrieve
      // image", camera.cpp:274-281); an exception would escape its converter loop
      return qi::AnyValue();
    }
    qi::AnyReferenceVector fields = typed.asTupleValuePtr();
    std::vector<qi::AnyValue> out;
    for (size_t i = 0; i < fields.size(); ++i) {
      if (i == 6) {
        std::pair<char*, size_t> raw = fields[i].asRaw();
        qi::Buffer buffer;
        buffer.write(raw.first, raw.second);
        out.push_back(qi::AnyValue::from(buffer));
      } else {
        out.push_back(qi::AnyValue(fields[i], true, true));
      }
    }
    return qi::AnyValue::from(out);
  };
  qi::DynamicObjectBuilder builder;
  builder.advertiseMethod("subscribeCamera", subscribe);
  builder.advertiseMethod("unsubscribe", unsubscribe);
  builder.advertiseMethod("getImageRemote", image);
  session->registerService("ALVideoDevice", builder.object()).value();
  std::cout << "video relay ready" << std::endl;
  qi::Promise<void> forever;
  forever.future().wait();
  return 0;
}
